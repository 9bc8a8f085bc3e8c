#!/usr/bin/python3
"""Gross checks against the geometry (estimators/diagnosis/gross_check.hpp) on a flight from the
independent generator (scripts/flightgen.py landing, seed 4): the same flight with one unit
mixed up in one file must be refused before any diagnosis, naming the file's column and the
likely unit; the flight as written, and the same flight with a large but real radar effect (a
range gain of 0.05, a 3 deg azimuth bias), is diagnosed as before; an azimuth-only flight
(flightgen uav, seed 3) with its bearings in radians is refused the same way.

  python3 test/check_units.py SOURCE_DIR BUILD_DIR
"""
import csv
import json
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from generated_checks import Checks, run  # noqa: E402
import generated_checks  # noqa: E402

SRC, BUILD = sys.argv[1], sys.argv[2]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
checks = Checks("check_units")
check = checks.check


def rewrite(folder, name, column, f):
    """Column `column` of folder/name (CSV) replaced by f(value)."""
    path = os.path.join(folder, name)
    with open(path) as fh:
        rows = list(csv.reader(fh))
    i = rows[0].index(column)
    for r in rows[1:]:
        r[i] = repr(f(float(r[i])))
    with open(path, "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)


def variant(tmp, base, tag, edit):
    d = os.path.join(tmp, tag)
    shutil.copytree(base, d)
    edit(d)
    return run(DIAG, "prl", d, "--injections", "0", "--json", d + ".json")


def site_radians(d):
    path = os.path.join(d, "site.json")
    s = json.load(open(path))
    s["radar"]["azimuth_reference_deg"] = math.radians(s["radar"]["azimuth_reference_deg"])
    json.dump(s, open(path, "w"))


def main():
    tmp = tempfile.mkdtemp(prefix="check_units.")
    base = os.path.join(tmp, "flight")
    generated_checks.gen(SRC, "check_units", "landing", base, 4, [])
    cases = [
        ("range in kilometres", lambda d: rewrite(d, "radar.csv", "range_m", lambda x: x / 1000),
         "radar.csv range_m looks like kilometres"),
        ("range in feet", lambda d: rewrite(d, "radar.csv", "range_m", lambda x: x / 0.3048),
         "radar.csv range_m looks like feet"),
        ("azimuths in radians", lambda d: rewrite(d, "radar.csv", "azimuth_deg", math.radians),
         "radar.csv azimuth_deg looks like radians"),
        ("elevations in radians", lambda d: rewrite(d, "radar.csv", "elevation_deg", math.radians),
         "radar.csv elevation_deg looks like radians"),
        ("elevations in milliradians", lambda d: rewrite(d, "radar.csv", "elevation_deg", lambda x: 1000 * math.radians(x)),
         "radar.csv elevation_deg looks like milliradians"),
        # (17.45 times the degrees: they wrap past 180 on this flight; the slope is taken on the
        # azimuths made continuous)
        ("azimuths in milliradians", lambda d: rewrite(d, "radar.csv", "azimuth_deg", lambda x: 1000 * math.radians(x)),
         "radar.csv azimuth_deg looks like milliradians"),
        ("azimuth reference in radians", site_radians, "site.json radar.azimuth_reference_deg looks like radians"),
        ("nav heights in feet", lambda d: rewrite(d, "nav.csv", "h_m", lambda x: x / 0.3048), "nav.csv h_m looks like feet"),
    ]
    for what, edit, expected in cases:
        p = variant(tmp, base, what.replace(" ", "_"), edit)
        check(p.returncode == 2 and expected in p.stderr,
              "%s: refused, naming it ('%s'): exit %d, %s" % (what, expected, p.returncode, p.stderr.strip()[-240:]))
    for what, edit in (("as written", lambda d: None),
                       ("a range gain of 0.05", lambda d: rewrite(d, "radar.csv", "range_m", lambda x: 1.05 * x)),
                       ("a 3 deg azimuth bias", lambda d: rewrite(d, "radar.csv", "azimuth_deg", lambda x: x + 3))):
        p = variant(tmp, base, what.replace(" ", "_"), edit)
        check(p.returncode == 0, "%s: diagnosed (exit %d%s)" % (what, p.returncode, ", " + p.stderr.strip()[-200:] if p.returncode else ""))
    # an azimuth-only flight (the UAV orbiting a boat, seed 3) with its bearings in radians
    uav = os.path.join(tmp, "uav")
    generated_checks.gen(SRC, "check_units", "uav", uav, 3, [])
    for what, edit, refused in (("as written", lambda d: None, False),
                                ("bearings in radians", lambda d: rewrite(d, "bearings.csv", "bearing_deg",
                                                                         lambda x: math.radians(x % 360)), True)):
        d = os.path.join(tmp, "uav_" + what.replace(" ", "_"))
        shutil.copytree(uav, d)
        edit(d)
        p = run(DIAG, "uav", d, "--injections", "0")
        if refused:
            check(p.returncode == 2 and "bearings.csv bearing_deg looks like radians" in p.stderr,
                  "uav, %s: refused, naming it: exit %d, %s" % (what, p.returncode, p.stderr.strip()[-200:]))
        else:
            check(p.returncode == 0, "uav, %s: diagnosed (exit %d)" % (what, p.returncode))
    shutil.rmtree(tmp, ignore_errors=True)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
