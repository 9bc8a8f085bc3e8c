#!/usr/bin/python3
"""A hardware entry the pooled diagnosis names agrees across its recordings in the final model.

The multi-sensor diagnosis names a hardware entry (one value in every recording) only when the
random-effects mean of its per-recording values differs from zero at alpha (Hartung-Knapp; the
JSON's `replication.log10_p`). That must hold given the model the report names, not only given
the entries chosen when it was checked: an entry that agreed only beside another that then left
must leave too. On the eight Autoferry recordings without scenario 6, a single pass of that check
named the radar's clock (2.72 s) with its own replication p = 0.017 > alpha = 0.01; run until
nothing changes, every hardware entry named has p < alpha. The check below asserts, for every
named entry with a replication, log10 p < log10 alpha: it fails with the single pass.

  python3 test/check_pooled_agreement.py SOURCE_DIR BUILD_DIR DATA_DIR
"""
import json
import math
import os
import re
import sys
import tempfile

from generated_checks import Checks, run

SRC, BUILD, DATA = sys.argv[1], sys.argv[2], sys.argv[3]
AUTOFERRY = os.path.join(DATA, "autoferry")
# Scenario -> the import's boat names (target 2 is Gunnerus in the first week, the jetboat after).
SCENARIOS = [(2, "havfruen,gunnerus"), (3, "havfruen,gunnerus"), (4, "havfruen,gunnerus"), (5, "havfruen,gunnerus"),
             (13, "havfruen,jetboat"), (16, "havfruen,jetboat"), (17, "havfruen,jetboat"), (22, "havfruen,jetboat")]
checks = Checks("check_pooled_agreement")
check = checks.check

if not os.path.isdir(AUTOFERRY):
    raise SystemExit("check_pooled_agreement: %s is missing (the Autoferry recordings of the repository, test/data)" % AUTOFERRY)

with tempfile.TemporaryDirectory(prefix="check_pooled_agreement.") as tmp:
    dirs = []
    for sc, boats in SCENARIOS:
        d = os.path.join(tmp, "sc%d" % sc)
        r = run(os.path.join(BUILD, "bin", "rnav_import_autoferry"), os.path.join(AUTOFERRY, "scenario%d" % sc),
                "--out", d, "--boat-names", boats)
        if r.returncode != 0:
            raise SystemExit("check_pooled_agreement: import of scenario %d failed: %s" % (sc, r.stderr))
        dirs.append(d)
    out = os.path.join(tmp, "pooled.json")
    r = run(os.path.join(BUILD, "bin", "rnav_diagnose"), "multi", *dirs, "--no-leave-one-out", "--threads", "2",
            "--json", out)
    if r.returncode != 0:
        raise SystemExit("check_pooled_agreement: the pooled diagnosis failed: %s" % r.stderr)
    with open(out) as f:
        j = json.load(f)

m = re.match(r"alpha = ([0-9.eE+-]+) ", j["familywise"])
check(m is not None, "the report states its alpha (%s)" % j["familywise"][:40])
alpha = float(m.group(1)) if m else 0.01
hardware = [e for e in j["effects"] if e.get("replication")]
check(len(hardware) >= 1, "at least one hardware entry named with its recordings' values (%d)" % len(hardware))
for e in hardware:
    lp = e["replication"]["log10_p"]
    where = e["scope"].get("sensor") or e["scope"].get("target")
    check(lp < math.log10(alpha), "%s [%s]: its recordings agree, log10 p %.2f < log10 alpha %.2f (values %s)"
          % (e["name"], where, lp, math.log10(alpha),
             ", ".join("%.3g" % v[0] for v in e["replication"]["estimate"])))

sys.exit(checks.finish())
