#!/usr/bin/python3
"""The calibration check and scan on real recordings (Autoferry scenarios 13, 16 and 22).

rnav_diagnose multi DIR... --apply FILE removes the hardware effects of FILE from each recording
and scores each sensor:target pair; scripts/calibration_scan applies a grid of them. Checked:
  * the lidar's clock applied changes the lidar's pairs only (every camera and radar pair's
    calibrated error is its nominal one, exactly); a boat the recordings lack is listed as not
    applied; an unknown effect name is an error naming it; the same calibration in a
    "calibrations" list (the scan's grid form) scores the same, row for row;
  * the scan's best calibration within the bound keeps every pair within it, its geometric mean
    lies between the best without the bound and 1 (no calibration is on the grid), and applied
    on its own through --apply it gives the same geometric mean;
  * effects on disjoint pairs (the lidar's and the radar's clocks) are scanned apart, the grid
    of each alone (5 + 5 calibrations, not 25);
  * a sensor no recording has is refused, naming it.

  python3 test/check_calibration_scan.py SOURCE_DIR BUILD_DIR DATA_DIR
"""
import json
import math
import os
import sys
import tempfile

from generated_checks import Checks, run

SRC, BUILD, DATA = sys.argv[1], sys.argv[2], sys.argv[3]
AUTOFERRY = os.path.join(DATA, "autoferry")
SCENARIOS = [13, 16, 22]  # the jetboat's week: target 2 is the jetboat
DIAGNOSE = os.path.join(BUILD, "bin", "rnav_diagnose")
SCAN = os.path.join(SRC, "scripts", "calibration_scan")
TOLERANCE = 1.10
checks = Checks("check_calibration_scan")
check = checks.check

if not os.path.isdir(AUTOFERRY):
    raise SystemExit("check_calibration_scan: %s is missing (the Autoferry recordings of the repository, test/data)" % AUTOFERRY)


def geomean(rows, min_n=5):
    r = [x["calibrated_rms"] / x["nominal_rms"] for x in rows if x["n"] >= min_n]
    return math.exp(sum(math.log(v) for v in r) / len(r))


with tempfile.TemporaryDirectory(prefix="check_calibration_scan.") as tmp:
    dirs = []
    for sc in SCENARIOS:
        d = os.path.join(tmp, "sc%d" % sc)
        r = run(os.path.join(BUILD, "bin", "rnav_import_autoferry"), os.path.join(AUTOFERRY, "scenario%d" % sc),
                "--out", d, "--boat-names", "havfruen,jetboat")
        if r.returncode != 0:
            raise SystemExit("check_calibration_scan: import of scenario %d failed: %s" % (sc, r.stderr))
        dirs.append(d)

    # --apply: the lidar's clock, and a hull offset on a boat of the other week
    cal = os.path.join(tmp, "cal.json")
    with open(cal, "w") as f:
        json.dump({"effects": [{"name": "time_offset", "scope": {"sensor": "lidar"}, "estimate": 0.5},
                               {"name": "antenna_offset", "scope": {"sensor": "radar", "target": "gunnerus"},
                                "estimate": [-7, 0]}]}, f)
    out = os.path.join(tmp, "applied.json")
    r = run(DIAGNOSE, "multi", *dirs, "--apply", cal, "--json", out)
    check(r.returncode == 0, "--apply runs (%s)" % r.stderr.strip()[-200:])
    rep = json.load(open(out)) if r.returncode == 0 else {"rows": [], "applied": {}, "not_applied_absent": []}
    lidar = [x for x in rep["rows"] if x["pair"].startswith("lidar:")]
    others = [x for x in rep["rows"] if not x["pair"].startswith("lidar:")]
    check(len(lidar) == 6 and all(x["calibrated_rms"] != x["nominal_rms"] for x in lidar),
          "the lidar's clock changes each of its 6 pairs (%d)" % len(lidar))
    check(len(others) >= 12 and all(x["calibrated_rms"] == x["nominal_rms"] for x in others),
          "and no camera or radar pair (%d pairs, calibrated = nominal)" % len(others))
    check(rep["not_applied_absent"] == ["antenna_offset@radar:gunnerus"],
          "Gunnerus, absent from these recordings, is listed as not applied (%s)" % rep["not_applied_absent"])
    check(all(rep["applied"].get("sc%d" % sc) == ["time_offset@sensor lidar (s=0.5)"] for sc in SCENARIOS),
          "each recording names what it applied (%s)" % rep["applied"])
    # the same calibration in a "calibrations" list (as the scan writes its grid), beside none
    with open(cal, "w") as f:
        json.dump({"calibrations": [{"effects": [{"name": "time_offset", "scope": {"sensor": "lidar"}, "estimate": 0.5}]},
                                    {"effects": []}]}, f)
    r = run(DIAGNOSE, "multi", *dirs, "--apply", cal, "--json", out)
    batch = json.load(open(out))["calibrations"] if r.returncode == 0 else [{"rows": None}, {"rows": []}]
    check(r.returncode == 0 and len(batch) == 2 and batch[0]["rows"] == rep["rows"],
          "a calibrations list scores its first calibration as --apply of it alone (%s)" % r.stderr.strip()[-200:])
    check(len(batch[1]["rows"]) == len(rep["rows"]) and all(x["calibrated_rms"] == x["nominal_rms"] for x in batch[1]["rows"]),
          "and its empty second calibration changes no pair")
    with open(cal, "w") as f:
        json.dump({"effects": [{"name": "time_ofset", "scope": {"sensor": "lidar"}, "estimate": 0.5}]}, f)
    r = run(DIAGNOSE, "multi", *dirs, "--apply", cal)
    check(r.returncode != 0 and "no catalogue entry is named 'time_ofset' (did you mean 'time_offset'?)" in r.stderr,
          "an unknown effect name is an error naming it (%s)" % r.stderr.strip()[-160:])

    # the scan: two clocks on disjoint pairs, five values each
    scan_json = os.path.join(tmp, "scan.json")
    r = run(SCAN, *dirs, "--effect", "time_offset@lidar=0:1:0.25", "--effect", "time_offset@radar=0:2:0.5",
            "--tolerance", str(TOLERANCE), "--json", scan_json)
    check(r.returncode == 0, "calibration_scan runs (%s)" % r.stderr.strip()[-200:])
    s = json.load(open(scan_json)) if r.returncode == 0 else {"groups": [], "all": {}}
    check([g["calibrations"] for g in s["groups"]] == [5, 5],
          "the two clocks are scanned apart, five calibrations each (%s)" % [g["calibrations"] for g in s["groups"]])
    al = s["all"]
    check(al.get("worst_bounded", 9) <= TOLERANCE, "the best within the bound keeps every pair within it (%s)" % al.get("worst_bounded"))
    check(al.get("geomean_free", 9) <= al.get("geomean_bounded", 0) <= 1,
          "best without the bound <= best within it <= 1 (%s, %s)" % (al.get("geomean_free"), al.get("geomean_bounded")))
    # the bounded choice applied on its own gives the scan's figure
    chosen = {}
    for g in s["groups"]:
        chosen.update(g["bounded"])
    effects = [{"name": k.split("@")[0], "scope": {"sensor": k.split("@")[1]}, "estimate": v} for k, v in chosen.items()]
    with open(cal, "w") as f:
        json.dump({"effects": effects}, f)
    r = run(DIAGNOSE, "multi", *dirs, "--apply", cal, "--json", out)
    if r.returncode == 0 and effects:
        g = geomean(json.load(open(out))["rows"])
        check(abs(g - al["geomean_bounded"]) < 1e-9,
              "the chosen calibration (%s) applied alone: geometric mean %.6f = the scan's %.6f" % (chosen, g, al["geomean_bounded"]))
    else:
        check(False, "the chosen calibration applies (%s)" % r.stderr.strip()[-200:])
    r = run(SCAN, *dirs, "--effect", "time_offset@lidr=0:1:0.5")
    check(r.returncode != 0 and "time_offset@sensor lidr" in r.stderr, "a sensor no recording has is refused, naming it (%s)" % r.stderr.strip())

sys.exit(checks.finish())
