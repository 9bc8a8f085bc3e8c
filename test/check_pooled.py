#!/usr/bin/python3
"""Several recordings diagnosed together, on the independent generator's ship radar
(scripts/flightgen.py shipradar, four 5-minute recordings of 8 other ships each, own-ship
courses and seeds; 10 minutes of 15 ships each pass the same checks in five times the time), through the command line as a user runs it:

1. a radar bearing bias of 0.3 deg hidden in all four is named once, as the radar's hardware
   (no recording in its scope), within 3 SE, with each recording's value in `replication`;
2. a radar range bias of 60 m hidden in the second recording only is named as that recording's
   own (scope recording "r2"), within 3 SE, and not as hardware;
3. `leave_one_out` has a row per recording and radar:target pair with n > 0, and leaving each
   recording out the hardware bias carried lowers that recording's radar error (summed over its
   ships: the bias is 26 m at 5 km against 15 m of range noise);
4. the hardware bias is carried whole by the default carry rule (JSON `carry`: share 1, every
   recording sharing it);
5. the command line refuses two folders of one name, several INPUTs for another KIND, and a
   carry tolerance below 1.

  python3 test/check_pooled.py SOURCE_DIR BUILD_DIR
"""
import json
import math
import os
import sys
import tempfile

from generated_checks import Checks, run
import generated_checks

SRC, BUILD = sys.argv[1], sys.argv[2]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
KEYS = ["duration_s=300", "place_time_frac=0", "bearing_bias_deg=0.3", "n_targets=8"]
OPTS = ["--gate-m", "300", "--sigma-range-m", "15", "--sigma-deg", "0.5", "--threads", "2", "--reference-max-gap", "12"]
checks = Checks("check_pooled")
check = checks.check

with tempfile.TemporaryDirectory(prefix="check_pooled.") as tmp:
    dirs = []
    for k, seed in enumerate((21, 22, 23, 24), start=1):
        d = os.path.join(tmp, "r%d" % k)
        extra = ["range_bias_m=60"] if k == 2 else []
        generated_checks.gen(SRC, "check_pooled", "shipradar", d, seed, KEYS + extra)
        dirs.append(d)
    out = os.path.join(tmp, "pooled.json")
    p = run(DIAG, "multi", *dirs, "--json", out, *OPTS)
    check(p.returncode == 0, "pooled diagnosis of four recordings runs: %s" % p.stderr.strip()[-300:])
    if p.returncode == 0:
        rep = json.load(open(out))
        check(rep.get("recordings") == ["r1", "r2", "r3", "r4"], "recordings named by their folders: %s" % rep.get("recordings"))
        eff = [e for e in rep["effects"] if e["name"] not in ("target_maneuver", "noise_scale", "correlated_noise", "outliers")]
        named = ["%s[%s]" % (e["name"], e["scope"]) for e in eff]
        bias = [e for e in eff if e["name"] == "bearing_bias" and e["scope"]["sensor"] == "radar"]
        hw = [e for e in bias if not e["scope"].get("recording")]
        check(len(hw) == 1 and abs(hw[0]["estimate"] - math.radians(0.3)) < 3 * hw[0]["stderr"],
              "the 0.3 deg bearing bias is the radar's hardware, within 3 SE: %s" % named)
        check(len(hw) == 1 and len(hw[0].get("replication", {}).get("recordings", [])) == 4,
              "its value in each of the four recordings is reported (replication)")
        rb = [e for e in eff if e["name"] == "range_bias"]
        own = [e for e in rb if e["scope"].get("recording") == "r2"]
        check(len(own) == 1 and abs(own[0]["estimate"] - 60) < 3 * own[0]["stderr"],
              "the 60 m range bias is recording r2's own, within 3 SE: %s" % named)
        check(not [e for e in rb if not e["scope"].get("recording")], "no hardware range bias")
        carry = [c for c in rep.get("carry", {}).get("effects", []) if c["name"] == "bearing_bias" and c["scope"]["sensor"] == "radar"]
        check(len(carry) == 1 and carry[0]["share"] == 1 and rep["carry"]["tolerance"] == 1,
              "the bias every recording shares is carried whole by the default carry rule: %s" % carry)
        rows = rep["leave_one_out"]
        for rec in ("r1", "r2", "r3", "r4"):
            mine = [x for x in rows if x["recording"] == rec and x["pair"].startswith("radar:") and x["n"] > 0]
            nom = sum(x["n"] * x["nominal_rms"] ** 2 for x in mine)
            ext = sum(x["n"] * x["extended_rms"] ** 2 for x in mine)
            check(mine and ext < nom, "leaving out %s: its radar error falls with the carried bias (%.1f -> %.1f m RMS over %d ships)"
                  % (rec, math.sqrt(nom / max(1, sum(x["n"] for x in mine))), math.sqrt(ext / max(1, sum(x["n"] for x in mine))), len(mine)))
    p = run(DIAG, "multi", dirs[0], dirs[1], "--carry-tolerance", "0.5", *OPTS)
    check(p.returncode == 2 and "tolerance must be >= 1" in p.stderr, "a carry tolerance below 1 refused: %s" % p.stderr.strip()[-200:])
    twin = os.path.join(tmp, "other", "r1")
    os.makedirs(os.path.dirname(twin))
    os.symlink(dirs[0], twin)
    p = run(DIAG, "multi", dirs[0], twin, *OPTS)
    check(p.returncode == 2 and "both named 'r1'" in p.stderr, "two folders named r1 refused: %s" % p.stderr.strip()[-200:])
    p = run(DIAG, "uav", dirs[0], dirs[1])
    check(p.returncode == 2 and "only multi takes several" in p.stderr, "uav with two INPUTs refused: %s" % p.stderr.strip()[-200:])

sys.exit(checks.finish())
