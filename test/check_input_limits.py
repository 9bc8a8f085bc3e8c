#!/usr/bin/python3
"""rnav_diagnose --max-rows: data with more rows than the limit (radar plots, bearings, detection
rows over all recordings) are refused before the diagnosis, exit 2, naming the input, the count
and the option; at or under the limit they are diagnosed. Data from the independent generator
(scripts/flightgen.py): a 5 Hz landing flight, an azimuth-only flight, a small multi-sensor
recording (given twice, as two recordings, the count is their sum).

  python3 test/check_input_limits.py SOURCE_DIR BUILD_DIR
"""
import os
import shutil
import sys
import tempfile

from generated_checks import Checks, run
import generated_checks

SRC, BUILD = sys.argv[1], sys.argv[2]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
checks = Checks("check_input_limits")
check = checks.check


def rows(path):
    """Data rows of a CSV (its lines but the header)."""
    with open(path) as f:
        return sum(1 for _ in f) - 1


def main():
    tmp = tempfile.mkdtemp(prefix="check_input_limits.")
    land, uav, ship = (os.path.join(tmp, m) for m in ("landing", "uav", "ship"))
    generated_checks.gen(SRC, "check_input_limits", "landing", land, 4, ["rate_hz=5"])
    generated_checks.gen(SRC, "check_input_limits", "uav", uav, 3, [])
    generated_checks.gen(SRC, "check_input_limits", "shipradar", ship, 4, ["duration_s=300", "n_targets=5"])
    ship2 = os.path.join(tmp, "ship2")
    shutil.copytree(ship, ship2)
    n_land, n_uav, n_ship = rows(os.path.join(land, "radar.csv")), rows(os.path.join(uav, "bearings.csv")), \
        rows(os.path.join(ship, "detections.csv"))
    cases = [  # (what, argv, rows, noun)
        ("landing", ["prl", land], n_land, "radar plots"),
        ("azimuth-only", ["uav", uav], n_uav, "bearings"),
        ("multi-sensor, two recordings", ["multi", ship, ship2, "--reference-max-gap", "12", "--no-leave-one-out"],
         2 * n_ship, "detection rows"),
    ]
    for what, argv, n, noun in cases:
        p = run(DIAG, *argv, "--injections", "0", "--max-rows", str(n - 1))
        expected = "%d %s, more than the %d diagnosed at most (--max-rows N raises it" % (n, noun, n - 1)
        check(p.returncode == 2 and expected in p.stderr,
              "%s: %d rows over a limit of %d refused, naming them ('%s'): exit %d, %s"
              % (what, n, n - 1, expected, p.returncode, p.stderr.strip()[-200:]))
        p = run(DIAG, *argv, "--injections", "0", "--max-rows", str(n))
        check(p.returncode == 0, "%s: %d rows at a limit of %d diagnosed: exit %d %s"
              % (what, n, n, p.returncode, p.stderr.strip()[-200:]))
    p = run(DIAG, "prl", land, "--max-rows", "0")
    check(p.returncode == 2 and "--max-rows" in p.stderr, "--max-rows 0 is refused, naming the option: exit %d, %s"
          % (p.returncode, p.stderr.strip()))
    shutil.rmtree(tmp, ignore_errors=True)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
