#!/usr/bin/python3
"""The reference-jump check on the real recording where it fires (Autoferry scenario 6), through
the command line as a user runs it (scripts/diagnose multi DIR --plots DIR):

  * the text report and the JSON name Havfruen's reference jump 88.9 s after its first sample
    (within 0.5 s), and only that one (Gunnerus's reference is clean), with the stretch used
    ending before it;
  * after the cut no lidar detection of Havfruen is left to score (its lidar detections all come
    after 80 s, most after the jump: JSON gain has no lidar:havfruen pair), while with
    --reference-jump-accel 0 the lidar's Havfruen pair is scored against the jumped reference
    with a held-out error above 5 m (lidar noise is about 1 m; the jump moves the reference 5-10 m);
  * --plots draws reference_jump_havfruen.png (a PNG, non-empty) and no jump figure without a jump;
  * a negative --reference-jump-accel is refused, naming it.

  python3 test/check_reference_jump.py SOURCE_DIR BUILD_DIR DATA_DIR
"""
import json
import os
import sys
import tempfile

from generated_checks import Checks, run

SRC, BUILD, DATA = sys.argv[1], sys.argv[2], sys.argv[3]
SCENARIO = os.path.join(DATA, "autoferry", "scenario6")
DIAGNOSE = os.path.join(SRC, "scripts", "diagnose")
JUMP_AFTER_FIRST_S = 88.9  # docs/autoferry-multi-sensor.md
checks = Checks("check_reference_jump")
check = checks.check

if not os.path.isdir(SCENARIO):
    raise SystemExit("check_reference_jump: %s is missing (the Autoferry recordings of the repository, test/data)" % SCENARIO)

with tempfile.TemporaryDirectory(prefix="check_reference_jump.") as tmp:
    d = os.path.join(tmp, "sc6")
    r = run(os.path.join(BUILD, "bin", "rnav_import_autoferry"), SCENARIO, "--out", d, "--boat-names", "havfruen,gunnerus")
    if r.returncode != 0:
        raise SystemExit("check_reference_jump: import of scenario 6 failed: %s" % r.stderr)
    first_t = min(float(line.split(",")[0]) for line in open(os.path.join(d, "truth.csv")).read().splitlines()[1:]
                  if line.split(",")[1] == "havfruen")

    plots = os.path.join(tmp, "plots")
    p = run(DIAGNOSE, "multi", d, "--plots", plots)
    check(p.returncode == 0, "scripts/diagnose multi sc6 --plots runs: %s" % p.stderr.strip()[-300:])
    check("reference havfruen: jumps" in p.stdout, "the text report names Havfruen's reference jump")
    check("reference gunnerus" not in p.stdout, "and no jump of Gunnerus's")
    rep = json.load(open(os.path.join(plots, "diagnosis.json")))
    jumps = rep.get("reference_jumps", [])
    check(len(jumps) == 1 and jumps[0]["target"] == "havfruen" and jumps[0]["recording"] == "",
          "JSON reference_jumps: one, Havfruen's: %s" % jumps)
    if len(jumps) == 1:
        j = jumps[0]
        check(abs(j["t_s"] - first_t - JUMP_AFTER_FIRST_S) < 0.5,
              "the jump %.2f s after the reference's first sample (%.1f documented)" % (j["t_s"] - first_t, JUMP_AFTER_FIRST_S))
        check(j["deviation_m"] > j["bound_m"] and j["used_to_s"] < j["t_s"] and j["samples_used"] < j["samples"],
              "off its chord beyond the bound (%.2f > %.2f m), the stretch used ending before it" % (j["deviation_m"], j["bound_m"]))
    check("lidar:havfruen" not in rep.get("gain", {}), "no lidar:havfruen held-out pair after the cut")
    png = os.path.join(plots, "reference_jump_havfruen.png")
    check(os.path.isfile(png) and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(png) > 10000,
          "--plots draws reference_jump_havfruen.png")

    off = os.path.join(tmp, "off")
    p = run(DIAGNOSE, "multi", d, "--plots", off, "--reference-jump-accel", "0")
    check(p.returncode == 0, "with --reference-jump-accel 0 it runs: %s" % p.stderr.strip()[-300:])
    if p.returncode == 0:
        rep = json.load(open(os.path.join(off, "diagnosis.json")))
        check(rep.get("reference_jumps") == [], "no jump named with the check off")
        g = rep.get("gain", {}).get("lidar:havfruen")
        check(g is not None and g["nominal_rms"] > 5,
              "the lidar's Havfruen pair then scored against the jumped reference: held-out RMS %s m" % (g and round(g["nominal_rms"], 2)))
        check(not [f for f in os.listdir(off) if f.startswith("reference_jump")], "and no jump figure drawn")

    p = run(os.path.join(BUILD, "bin", "rnav_diagnose"), "multi", d, "--reference-jump-accel", "-1")
    check(p.returncode != 0 and "reference_jump_accel" in p.stderr, "a negative --reference-jump-accel refused: %s" % p.stderr.strip()[-200:])

sys.exit(checks.finish())
