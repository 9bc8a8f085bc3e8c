#!/usr/bin/python3
"""Gross unit checks (estimators/diagnosis/gross_check.hpp, common/io/plausible.hpp) in every file of
the three CSV formats, on data from the independent generator (scripts/flightgen.py): the same
data with one column in another unit (kilometres, feet, radians, milliradians) must be refused
before any diagnosis, exit 2, naming the file's column and the likely unit. The data as written,
and the same data with a large but real sensor effect (a range gain of 0.05, a 3 deg azimuth bias,
a 0.5 deg elevation bias, a 2 deg bearing bias), are diagnosed (exit 0).

  landing   (flightgen landing, seed 4):     radar.csv, nav.csv, truth.csv, site.json
  azimuth   (flightgen uav, seed 3):         bearings.csv, observer.csv, truth.csv
  multi     (flightgen shipradar, seed 4, 10 targets for 600 s; AIS-like reference, hence
             --reference-max-gap 12):        detections.csv, observer.csv, truth.csv

Not checked, because the diagnosis does not use them: site.json's runway heading and threshold
height (carried to exports only) and the observer's height in the 2-D azimuth-only and
multi-sensor diagnoses (it enters only through the frame's curvature).

  python3 test/check_units.py SOURCE_DIR BUILD_DIR
"""
import csv
import json
import math
import os
import shutil
import sys
import tempfile

from generated_checks import Checks, run
import generated_checks

SRC, BUILD = sys.argv[1], sys.argv[2]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
checks = Checks("check_units")
check = checks.check

KM = lambda x: x / 1000  # noqa: E731  (a length in metres written as kilometres)
FT = lambda x: x / 0.3048  # noqa: E731
RAD = math.radians
MRAD = lambda x: 1000 * math.radians(x)  # noqa: E731


def rewrite(name, column, f):
    """An edit: column `column` of the folder's CSV `name` replaced by f(value) (empty cells kept)."""
    def edit(folder):
        path = os.path.join(folder, name)
        with open(path) as fh:
            rows = list(csv.reader(fh))
        i = rows[0].index(column)
        for r in rows[1:]:
            if r[i] != "":
                r[i] = repr(f(float(r[i])))
        with open(path, "w", newline="") as fh:
            csv.writer(fh, lineterminator="\n").writerows(rows)
    return edit


def site(section, key, f):
    """An edit: site.json's section.key replaced by f(value)."""
    def edit(folder):
        path = os.path.join(folder, "site.json")
        s = json.load(open(path))
        s[section][key] = f(s[section][key])
        json.dump(s, open(path, "w"))
    return edit


# (what, edit, the message's start) per format; the message names the file's column and the unit
LANDING = [
    ("range in kilometres", rewrite("radar.csv", "range_m", KM), "radar.csv range_m looks like kilometres"),
    ("range in feet", rewrite("radar.csv", "range_m", FT), "radar.csv range_m looks like feet"),
    ("azimuths in radians", rewrite("radar.csv", "azimuth_deg", RAD), "radar.csv azimuth_deg looks like radians"),
    # (17.45 times the degrees: they wrap past 180 on this flight; the slope is taken on the
    # azimuths made continuous)
    ("azimuths in milliradians", rewrite("radar.csv", "azimuth_deg", MRAD), "radar.csv azimuth_deg looks like milliradians"),
    ("elevations in radians", rewrite("radar.csv", "elevation_deg", RAD), "radar.csv elevation_deg looks like radians"),
    ("elevations in milliradians", rewrite("radar.csv", "elevation_deg", MRAD),
     "radar.csv elevation_deg looks like milliradians"),
    ("nav heights in feet", rewrite("nav.csv", "h_m", FT), "nav.csv h_m looks like feet"),
    ("nav heights in kilometres", rewrite("nav.csv", "h_m", KM), "nav.csv h_m looks like kilometres"),
    ("nav latitudes in radians", rewrite("nav.csv", "lat_deg", RAD), "nav.csv lat_deg looks like radians"),
    ("nav longitudes in radians", rewrite("nav.csv", "lon_deg", RAD), "nav.csv lon_deg looks like radians"),
    ("truth heights in feet", rewrite("truth.csv", "h_m", FT), "truth.csv h_m looks like feet"),
    ("truth heights in kilometres", rewrite("truth.csv", "h_m", KM), "truth.csv h_m looks like kilometres"),
    ("truth latitudes in radians", rewrite("truth.csv", "lat_deg", RAD), "truth.csv lat_deg looks like radians"),
    ("truth longitudes in radians", rewrite("truth.csv", "lon_deg", RAD), "truth.csv lon_deg looks like radians"),
    ("azimuth reference in radians", site("radar", "azimuth_reference_deg", RAD),
     "site.json radar.azimuth_reference_deg looks like radians"),
    ("site height in feet", site("radar", "h_m", FT), "site.json radar.h_m looks like feet"),
    ("site height in kilometres", site("radar", "h_m", KM), "site.json radar.h_m looks like kilometres"),
    ("site latitude in radians", site("radar", "lat_deg", RAD), "site.json radar.lat_deg looks like radians"),
    ("site longitude in radians", site("radar", "lon_deg", RAD), "site.json radar.lon_deg looks like radians"),
    ("runway threshold latitude in radians", site("runway", "threshold_lat_deg", RAD),
     "site.json runway.threshold_lat_deg looks like radians"),
]
LANDING_REAL = [
    ("a range gain of 0.05", rewrite("radar.csv", "range_m", lambda x: 1.05 * x)),
    ("a 3 deg azimuth bias", rewrite("radar.csv", "azimuth_deg", lambda x: x + 3)),
    ("a 0.5 deg elevation bias", rewrite("radar.csv", "elevation_deg", lambda x: x + 0.5)),
]
AZIMUTH = [
    ("bearings in radians", rewrite("bearings.csv", "bearing_deg", lambda x: math.radians(x % 360)),
     "bearings.csv bearing_deg looks like radians"),
    ("bearings in milliradians", rewrite("bearings.csv", "bearing_deg", lambda x: MRAD(x % 360)),
     "(milliradians in a degree column?)"),
    ("observer latitudes in radians", rewrite("observer.csv", "lat_deg", RAD), "observer.csv lat_deg looks like radians"),
    ("observer longitudes in radians", rewrite("observer.csv", "lon_deg", RAD), "observer.csv lon_deg looks like radians"),
    ("truth latitudes in radians", rewrite("truth.csv", "lat_deg", RAD), "truth.csv lat_deg looks like radians"),
    ("truth longitudes in radians", rewrite("truth.csv", "lon_deg", RAD), "truth.csv lon_deg looks like radians"),
]
AZIMUTH_REAL = [("a 2 deg bearing bias", rewrite("bearings.csv", "bearing_deg", lambda x: x + 2))]
MULTI = [
    ("ranges in kilometres", rewrite("detections.csv", "range_m", KM),
     "detections.csv range_m of sensor radar looks like kilometres"),
    ("ranges in feet", rewrite("detections.csv", "range_m", FT), "detections.csv range_m of sensor radar looks like feet"),
    ("bearings in radians", rewrite("detections.csv", "bearing_deg", RAD),
     "detections.csv bearing_deg of sensor radar looks like radians"),
    ("bearings in milliradians", rewrite("detections.csv", "bearing_deg", lambda x: MRAD(x % 360)),
     "(milliradians in a degree column?)"),
    ("observer latitudes in radians", rewrite("observer.csv", "lat_deg", RAD), "observer.csv lat_deg looks like radians"),
    ("observer longitudes in radians", rewrite("observer.csv", "lon_deg", RAD), "observer.csv lon_deg looks like radians"),
    ("observer headings in radians", rewrite("observer.csv", "heading_deg", RAD), "observer.csv heading_deg looks like radians"),
    ("truth latitudes in radians", rewrite("truth.csv", "lat_deg", RAD), "truth.csv lat_deg looks like radians"),
    ("truth longitudes in radians", rewrite("truth.csv", "lon_deg", RAD), "truth.csv lon_deg looks like radians"),
]
MULTI_REAL = [("a range gain of 0.05", rewrite("detections.csv", "range_m", lambda x: 1.05 * x)),
              ("a 2 deg bearing bias", rewrite("detections.csv", "bearing_deg", lambda x: (x + 2) % 360))]

FORMATS = [  # (label, flightgen mode, seed, keys, diagnosis kind, extra options, refused cases, real effects)
    ("landing", "landing", 4, [], "prl", [], LANDING, LANDING_REAL),
    ("azimuth-only", "uav", 3, [], "uav", [], AZIMUTH, AZIMUTH_REAL),
    ("multi-sensor", "shipradar", 4, ["duration_s=600", "n_targets=10"], "multi", ["--reference-max-gap", "12"],
     MULTI, MULTI_REAL),
]


def main():
    tmp = tempfile.mkdtemp(prefix="check_units.")
    for label, mode, seed, keys, kind, extra, refused, real in FORMATS:
        base = os.path.join(tmp, mode)
        generated_checks.gen(SRC, "check_units", mode, base, seed, keys)
        cases = [(w, e, m) for w, e, m in refused] + [("as written", lambda d: None, None)] + \
                [(w, e, None) for w, e in real]
        for what, edit, expected in cases:
            d = os.path.join(tmp, mode + "_" + what.replace(" ", "_"))
            shutil.copytree(base, d)
            edit(d)
            p = run(DIAG, kind, d, "--injections", "0", *extra)
            tail = p.stderr.strip()[-260:]
            if expected is None:
                check(p.returncode == 0, "%s, %s: diagnosed (exit %d%s)" % (label, what, p.returncode,
                                                                           ", " + tail if p.returncode else ""))
            else:
                check(p.returncode == 2 and expected in p.stderr,
                      "%s, %s: refused, naming it ('%s'): exit %d, %s" % (label, what, expected, p.returncode, tail))
            shutil.rmtree(d, ignore_errors=True)
    shutil.rmtree(tmp, ignore_errors=True)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
