#!/usr/bin/python3
"""Forty-eight bad inputs of our own across the three CSV formats (landing, azimuth-only,
multi-sensor), on data from the independent generator (scripts/flightgen.py), each with what it
must give (docs/reliability.md lists them):

  refused    exit 2 and the error names the file, column, record or cause (a part of the text);
  same       exit 0 and the very report of the data as written (the input is odd, not wrong);
  diagnosed  exit 0 and the report says what was left out or changed (a part of its text).

No case may give exit 0 with a result computed from misread data. Then real data that must not
be refused by the azimuth-only reference check (bearing_reference_check.hpp), which was set on
the flights here: Autoferry scenario 5's IR camera on Havfruen (another boat on her path
34 s behind fitted a shifted reference better in a first version) and scenario 17's EO camera
on Havfruen are diagnosed; scenario 17's IR camera on the jetboat (Havfruen follows her path
75.7 s later and the camera sees Havfruen in 97 % of the frames) is refused naming both causes,
and diagnosed with --keep-references.

  python3 test/check_bad_inputs.py SOURCE_DIR BUILD_DIR DATA_DIR
"""
import csv
import json
import os
import shutil
import sys
import tempfile

from generated_checks import Checks, run
import generated_checks

SRC, BUILD, DATA = sys.argv[1], sys.argv[2], sys.argv[3]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
IMPORT = os.path.join(BUILD, "bin", "rnav_import_autoferry")
checks = Checks("check_bad_inputs")
check = checks.check


# --- edits of a folder -------------------------------------------------------------------------

def read_rows(folder, name):
    with open(os.path.join(folder, name)) as fh:
        return list(csv.reader(fh))


def write_rows(folder, name, rows):
    with open(os.path.join(folder, name), "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)


def col(name, column, f):
    """Column `column` of CSV `name` replaced by f(value) (empty cells kept)."""
    def edit(d):
        r = read_rows(d, name)
        i = r[0].index(column)
        for x in r[1:]:
            if x[i] != "":
                x[i] = repr(f(float(x[i])))
        write_rows(d, name, r)
    return edit


def set_col(name, column, value):
    """Every cell of a column set to `value`."""
    def edit(d):
        r = read_rows(d, name)
        i = r[0].index(column)
        for x in r[1:]:
            x[i] = value
        write_rows(d, name, r)
    return edit


def rows(name, f):
    """The data rows of CSV `name` through f(header, rows) -> (header, rows)."""
    def edit(d):
        r = read_rows(d, name)
        h, b = f(r[0], r[1:])
        write_rows(d, name, [h] + b)
    return edit


def text(name, f):
    """The file's text through f."""
    def edit(d):
        p = os.path.join(d, name)
        with open(p, encoding="utf-8") as fh:
            s = fh.read()
        with open(p, "w", encoding="utf-8", newline="") as fh:
            fh.write(f(s))
    return edit


def site(f):
    """site.json through f (in place)."""
    def edit(d):
        p = os.path.join(d, "site.json")
        s = json.load(open(p))
        f(s)
        json.dump(s, open(p, "w"))
    return edit


def remove(name):
    return lambda d: os.remove(os.path.join(d, name))


def swap_header(name, a, b):
    def f(h, body):
        h = list(h)
        i, j = h.index(a), h.index(b)
        h[i], h[j] = h[j], h[i]
        return h, body
    return rows(name, f)


def each(*edits):
    def edit(d):
        for e in edits:
            e(d)
    return edit


def twice(h, b):
    return h, [x for r in b for x in (r, list(r))]


def reverse(h, b):
    return h, b[::-1]


def first(n):
    return lambda h, b: (h, b[:n])


def cut(lo, hi):
    """The rows between fractions lo and hi of the file left out."""
    return lambda h, b: (h, b[:int(len(b) * lo)] + b[int(len(b) * hi):])


def copy_as(src, dst):
    return lambda d: shutil.copy(os.path.join(d, src), os.path.join(d, dst))


def same_track_as(new_id, old_id):
    return rows("truth.csv", lambda h, b: (h, b + [r[:1] + [new_id] + r[2:] for r in b if r[1] == old_id]))


# --- the cases: (what, edit, expectation, its text) ------------------------------------------------

REFUSED, SAME, DIAGNOSED = "refused", "same", "diagnosed"
LANDING = [
    ("every plot written twice", rows("radar.csv", twice), REFUSED, "radar.csv:3: column 't_s' is not in time order"),
    ("plots in reverse time order", rows("radar.csv", reverse), REFUSED, "radar.csv:3: column 't_s' is not in time order"),
    ("azimuths counter-clockwise from east (90 - az)", col("radar.csv", "azimuth_deg", lambda x: 90 - x), REFUSED,
     "radar.csv azimuth_deg is off the azimuth from nav.csv and site.json by a median"),
    ("azimuth and elevation headers swapped", swap_header("radar.csv", "azimuth_deg", "elevation_deg"), REFUSED,
     "radar.csv azimuth_deg does not scale with the angle from nav.csv"),
    ("elevations above 90 deg", col("radar.csv", "elevation_deg", lambda x: x + 95), REFUSED,
     "radar.csv:2: column 'elevation_deg' out of [-90, 90]"),
    ("negative ranges", col("radar.csv", "range_m", lambda x: -x), REFUSED, "radar.csv:2: column 'range_m' must be > 0"),
    ("radar.csv with its header only", rows("radar.csv", first(0)), REFUSED, "radar.csv: fewer than 10 plots"),
    ("radar.csv with 10 plots", rows("radar.csv", first(10)), REFUSED, "fewer than 30 plots with a nav solution around them"),
    ("a frozen radar: every plot the same values", each(set_col("radar.csv", "range_m", "35000"),
                                                          set_col("radar.csv", "azimuth_deg", "-6.4"),
                                                          set_col("radar.csv", "elevation_deg", "0.9")), REFUSED,
     "radar.csv range_m does not match the nav solution's geometry"),
    ("CRLF line endings (a Windows export)", text("radar.csv", lambda s: s.replace("\n", "\r\n")), SAME, None),
    ("a space before every comma", text("radar.csv", lambda s: s.replace(",", " ,")), SAME, None),
    ("header in capitals (T_S)", text("radar.csv", lambda s: s.replace("t_s", "T_S", 1)), REFUSED,
     "radar.csv:1: header lacks column 't_s'"),
    ("nav fixes at (0, 0): no GNSS fix", each(set_col("nav.csv", "lat_deg", "0"), set_col("nav.csv", "lon_deg", "0")), REFUSED,
     "(0, 0) is what a receiver without a fix writes"),
    ("nav.csv in reverse time order", rows("nav.csv", reverse), REFUSED, "nav.csv:3: column 't_s' is not in time order"),
    ("every nav fix written twice", rows("nav.csv", twice), REFUSED, "nav.csv:3: column 't_s' is not in time order"),
    ("nav.csv missing the middle half", rows("nav.csv", cut(0.25, 0.75)), DIAGNOSED, "dropped (no nav around them) 231"),
    ("nav in GPS time, 18 s ahead of the radar's and truth's UTC", col("nav.csv", "t_s", lambda x: x + 18), REFUSED,
     "truth.csv's time stamps look -18."),
    ("site.json without its runway", site(lambda s: s.pop("runway")), REFUSED,
     "site.json: scenario key 'runway.threshold_lat_deg' is required"),
    ("site.json with a key of another tool (radar.height_m)", site(lambda s: s["radar"].__setitem__("height_m", 10)), REFUSED,
     "site.json: unknown scenario key(s): radar.height_m"),
    ("site.json's radar 5 km below the sea", site(lambda s: s["radar"].__setitem__("h_m", -5000)), REFUSED,
     "scenario key 'radar.h_m': -5000 is out of range"),
    ("site.json's azimuth reference 400 deg", site(lambda s: s["radar"].__setitem__("azimuth_reference_deg", 400)), REFUSED,
     "scenario key 'radar.azimuth_reference_deg': 400 is out of range"),
    ("site.json missing", remove("site.json"), REFUSED, "site.json"),
    ("truth.csv missing (it is optional)", remove("truth.csv"), DIAGNOSED, "plots used 461"),
    ("truth.csv a copy of nav.csv", copy_as("nav.csv", "truth.csv"), DIAGNOSED, "gain truth_position_m: RMS"),
]
AZIMUTH = [
    ("reciprocal bearings (from the target to the observer)", col("bearings.csv", "bearing_deg", lambda x: (x + 180) % 360),
     REFUSED, "bearings.csv bearing_deg looks like the reciprocal bearing"),
    ("bearings counter-clockwise from east (90 - b)", col("bearings.csv", "bearing_deg", lambda x: (90 - x) % 360), REFUSED,
     "bearings.csv bearing_deg looks mirrored, counter-clockwise: its detections follow 90"),
    ("bearings frozen at one value", set_col("bearings.csv", "bearing_deg", "292.9"), REFUSED,
     "bearings.csv bearing_deg does not move"),
    ("bearings.csv with its header only", rows("bearings.csv", first(0)), REFUSED, "bearings.csv: fewer than 10 frames"),
    ("truth 60 s late", col("truth.csv", "t_s", lambda x: x + 60), REFUSED, "truth.csv's time stamps look +60."),
    ("truth 200 s early", col("truth.csv", "t_s", lambda x: x - 200), REFUSED, "truth.csv's time stamps look -199.9"),
    ("the observer 100 km north", col("observer.csv", "lat_deg", lambda x: x + 0.9), REFUSED,
     "do not follow the bearing from observer.csv to truth.csv's target"),
    ("the truth of a boat 20 km away", col("truth.csv", "lat_deg", lambda x: x + 0.18), REFUSED,
     "do not follow the bearing from observer.csv to truth.csv's target"),
    ("every bearing written twice (two detections, one place)", rows("bearings.csv", twice), SAME, None),
    ("observer.csv with 5 fixes", rows("observer.csv", first(5)), REFUSED, "observer.csv: 5 fixes; the observer's track needs at least 10"),
    ("the observer's track ends at a third", rows("observer.csv", cut(0.33, 1.0)), DIAGNOSED,
     "405 frames without an observer or truth sample around them left out"),
    ("truth.csv ends at half", rows("truth.csv", cut(0.5, 1.0)), DIAGNOSED,
     "over 0 to 149.9 s of the frames' 0 to 300 s: 303 frames without an observer or truth sample around them left out"),
    ("the bearing column named bearing_rad", text("bearings.csv", lambda s: s.replace("bearing_deg", "bearing_rad", 1)), REFUSED,
     "bearings.csv:1: header lacks column 'bearing_deg'"),
]
MULTI = [
    ("reciprocal bearings (+180 deg)", col("detections.csv", "bearing_deg", lambda x: (x + 180) % 360), REFUSED,
     "detections.csv bearing_deg of sensor radar looks like the reciprocal bearing"),
    ("range 0 where a range is unknown", set_col("detections.csv", "range_m", "0"), REFUSED,
     "column 'range_m' of sensor 'radar' is 0 in all its 2163 rows: no range"),
    ("detections in reverse time order", rows("detections.csv", reverse), REFUSED, "sensor 'radar' goes back in time"),
    ("a space after the sensor name on every other row",
     rows("detections.csv", lambda h, b: (h, [r[:1] + [r[1] + (" " if i % 2 else "")] + r[2:] for i, r in enumerate(b)])),
     SAME, None),
    ("target ids written 01, 02, ... in truth.csv", rows("truth.csv", lambda h, b: (h, [r[:1] + [r[1].zfill(2)] + r[2:] for r in b])),
     DIAGNOSED, "associated 01:"),
    ("one target's track also under a second id", same_track_as("99", "1"), REFUSED,
     "truth.csv: targets '1' and '99' have the same track"),
    ("truth.csv with one sample per target", rows("truth.csv", lambda h, b: (h, list({r[1]: r for r in b}.values()))), REFUSED,
     "truth.csv: every target has a single sample (10 targets); a reference track needs 2 or more"),
    ("every observer fix written twice", rows("observer.csv", twice), REFUSED, "observer.csv:3: column 't_s' is not in time order"),
    ("observer headings all 0 (no compass)", set_col("observer.csv", "heading_deg", "0"), REFUSED,
     "observer.csv heading_deg is 0 in every row while the observer's course over ground turns"),
    ("detections.csv with its header only", rows("detections.csv", first(0)), REFUSED, "detections.csv: no detections at all"),
    ("truth 100 s early", col("truth.csv", "t_s", lambda x: x - 100), REFUSED,
     "a time shift explains it: with truth.csv's times moved by 99."),
]

FORMATS = [  # (label, flightgen mode, seed, keys, diagnosis kind, extra options, cases)
    ("landing", "landing", 4, [], "prl", [], LANDING),
    ("azimuth-only", "uav", 3, [], "uav", [], AZIMUTH),
    ("multi-sensor", "shipradar", 4, ["duration_s=600", "n_targets=10"], "multi", ["--reference-max-gap", "12"], MULTI),
]


def real_camera_pairs(tmp):
    """Autoferry camera:target pairs the azimuth-only reference check must judge right."""
    for sc, sensor, target, refused in [(5, "ir", 1, None), (17, "eo", 1, None),
                                         (17, "ir", 2, "or the sensor sees another object that follows the target's path")]:
        d = os.path.join(tmp, "af%d_%s_%d" % (sc, sensor, target))
        r = run(IMPORT, os.path.join(DATA, "autoferry", "scenario%d" % sc), "--sensor", sensor, "--target", str(target),
                "--out", d)
        if r.returncode != 0:
            check(False, "import of Autoferry scenario %d %s:%d: %s" % (sc, sensor, target, r.stderr.strip()[-200:]))
            continue
        p = run(DIAG, "uav", d, "--injections", "0")
        what = "Autoferry scenario %d, %s on target %d" % (sc, sensor, target)
        if refused is None:
            check(p.returncode == 0, "%s: diagnosed (exit %d%s)" % (what, p.returncode, ", " + p.stderr.strip()[-200:] if p.returncode else ""))
        else:
            check(p.returncode == 2 and refused in p.stderr, "%s: refused naming '%s': exit %d, %s" % (what, refused, p.returncode,
                                                                                                   p.stderr.strip()[-240:]))
            k = run(DIAG, "uav", d, "--injections", "0", "--keep-references")
            check(k.returncode == 0, "%s with --keep-references: diagnosed (exit %d)" % (what, k.returncode))


def main():
    tmp = tempfile.mkdtemp(prefix="check_bad_inputs.")
    total = 0
    for label, mode, seed, keys, kind, extra, cases in FORMATS:
        base = os.path.join(tmp, mode)
        generated_checks.gen(SRC, "check_bad_inputs", mode, base, seed, keys)
        written = run(DIAG, kind, base, "--injections", "0", *extra)
        check(written.returncode == 0, "%s as written: diagnosed (exit %d)" % (label, written.returncode))
        for what, edit, expect, words in cases:
            total += 1
            d = os.path.join(tmp, "case")
            shutil.rmtree(d, ignore_errors=True)
            shutil.copytree(base, d)
            edit(d)
            p = run(DIAG, kind, d, "--injections", "0", *extra)
            tail = p.stderr.strip()[-260:]
            if expect == REFUSED:
                check(p.returncode == 2 and words in p.stderr,
                      "%s, %s: refused naming it ('%s'): exit %d, %s" % (label, what, words, p.returncode, tail))
            elif expect == SAME:
                check(p.returncode == 0 and p.stdout == written.stdout,
                      "%s, %s: the report of the data as written (exit %d%s)" % (label, what, p.returncode, ", " + tail if p.returncode else ""))
            else:
                check(p.returncode == 0 and words in p.stdout,
                      "%s, %s: diagnosed, saying '%s' (exit %d%s)" % (label, what, words, p.returncode, ", " + tail if p.returncode else ""))
    check(total == 48, "48 cases (%d)" % total)
    real_camera_pairs(tmp)
    shutil.rmtree(tmp, ignore_errors=True)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
