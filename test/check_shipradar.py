#!/usr/bin/python3
"""The multi-sensor diagnosis on a ship-radar recording from the independent generator
(scripts/flightgen.py shipradar), fixed seeds: a rotating radar on a moving own ship, 40 ships,
an AIS-like reference without heights reporting every 2-10 s. 7 minutes (about 5 800
detections) so the test stays short (the sparse reference of 4. 10 minutes: at 7 it has too few
turns to tell the two noise models apart); the full hour is scripts/flightgen.py's default.

1. nominal: a truth.csv without h_m is associated (more than 85 % of the detections: the rest
   fall where two ships are within two gates of each other, left out as ambiguous, or before a
   ship's first AIS report; before, the heights became NaN and nothing was associated), an AIS reference is refused by the default 2 s gap and
   taken with --reference-max-gap 12, and no mean effect is named;
2. a radar bearing bias of 0.3 deg (5 km: 26 m, inside the 300 m gate) is named, on the radar,
   within 3 standard errors;
3. a radar that stamps every detection of a scan with the sweep's end (stamp=scan, the
   generator's own code: latency ((beta0 - beta) mod 360) / omega, beta0 = 0) is named
   scan_time_offset on the radar, its sweep share within 3 SE of 1 and its constant within 3 SE
   of 0, the sweep's end within 15 deg (one grid step) plus 3 SE of beta0; no constant radar
   clock in its place;
4. a sparse reference of turning ships (AIS every 10-30 s, every ship turns, 2 m range noise,
   15 ships): the interpolation's own uncertainty (the chord's miss a b / 2, a from each ship's
   reference) is the nominal correlated component of range channels (stated in the JSON, at
   least 10 % of the nominal sigma, its correlation time the median AIS interval), and fewer
   channels are judged to carry correlated noise than with the reference taken as exact
   (--reference-accel 0: one acceleration bends a whole 10-30 s interval, a slow misfit the
   noise identification otherwise takes for correlated noise); no mean effect either way.

  python3 test/check_shipradar.py SOURCE_DIR BUILD_DIR
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
KEYS = ["place_time_frac=0"]
DURATION = "duration_s=420"  # unless the recording's keys give their own
OPTS = ["--gate-m", "300", "--sigma-range-m", "15", "--sigma-deg", "0.5", "--threads", "2"]
checks = Checks("check_shipradar")
check = checks.check


def gen(out, seed, *keys):
    own = any(k.startswith("duration_s=") for k in keys)
    generated_checks.gen(SRC, "check_shipradar", "shipradar", out, seed, KEYS + ([] if own else [DURATION]) + list(keys))


def diagnose(folder, out, *extra):
    return run(DIAG, "multi", folder, "--json", out, *OPTS, *extra)


def mean_effects(rep):
    return [e for e in rep["effects"] if e["name"] not in ("target_maneuver", "noise_scale", "correlated_noise", "outliers")]


def generated_report(tmp, name, *keys):
    """Seed 11's recording with `keys` set, diagnosed with the AIS gap allowed: its JSON report,
    or None (the failure checked and printed)."""
    folder = os.path.join(tmp, name)
    gen(folder, 11, *keys)
    out = os.path.join(tmp, name + ".json")
    p = diagnose(folder, out, "--reference-max-gap", "12")
    check(p.returncode == 0, "%s diagnosis runs: %s" % (name, p.stderr.strip()[-200:]))
    return json.load(open(out)) if p.returncode == 0 else None


with tempfile.TemporaryDirectory(prefix="check_shipradar.") as tmp:
    nominal = os.path.join(tmp, "nominal")
    gen(nominal, 11)
    with open(os.path.join(nominal, "truth.csv")) as f:
        check(f.readline().strip() == "t_s,target,lat_deg,lon_deg", "the reference has no h_m column")
    with open(os.path.join(nominal, "detections.csv")) as f:
        n_det = sum(1 for _ in f) - 1
    p = diagnose(nominal, os.path.join(tmp, "refused.json"))
    check(p.returncode != 0 and "no detection associated" in p.stderr,
          "the AIS reference is not interpolated across its gaps by default (2 s): %s" % p.stderr.strip()[-120:])
    p = diagnose(nominal, os.path.join(tmp, "nominal.json"), "--reference-max-gap", "12")
    check(p.returncode == 0, "nominal diagnosis runs: %s" % p.stderr.strip()[-200:])
    if p.returncode == 0:
        rep = json.load(open(os.path.join(tmp, "nominal.json")))
        assoc = sum(rep["association"]["radar"]["associated"].values())
        check(assoc > 0.85 * n_det, "%d of %d detections associated" % (assoc, n_det))
        named = ["%s[%s]" % (e["name"], e.get("scope")) for e in mean_effects(rep)]
        check(not named, "nominal recording: no mean effect named (%s)" % ", ".join(named))

    rep = generated_report(tmp, "biased", "bearing_bias_deg=0.3")
    if rep:
        found = [e for e in mean_effects(rep) if e["name"] == "bearing_bias"]
        ok = any(e["scope"]["sensor"] in ("radar", None) and
                 abs(e["estimate"] - math.radians(0.3)) < 3 * e["stderr"] for e in found)
        check(ok, "a 0.3 deg radar bearing bias named within 3 SE: %s" %
              ["%s %.5f +- %.5f" % (e["scope"], e["estimate"], e["stderr"]) for e in found])

    rep = generated_report(tmp, "stamped", "stamp=scan")
    if rep:
        found = [e for e in mean_effects(rep) if e["name"] == "scan_time_offset" and e["scope"]["sensor"] == "radar"]
        check(len(found) == 1, "scan_time_offset named on the radar: %s" % [e["name"] for e in mean_effects(rep)])
        if found:
            e = found[0]
            (c, f), (se_c, se_f) = e["estimate"], e["stderr"]
            end = e["scanned"]["value"]
            off = abs((end + 180) % 360 - 180)
            check(abs(f - 1) < 3 * se_f and abs(c) < 3 * se_c and off < 15 + 3 * e["scanned"]["stderr"],
                  "sweep share %.3f +- %.3f (1), constant %.3f +- %.3f s (0), sweep end %.0f deg (0)" % (f, se_f, c, se_c, end))
        clocks = [e for e in mean_effects(rep) if e["name"] == "time_offset" and e["scope"]["sensor"] == "radar"]
        check(not clocks, "no constant radar clock in its place")

    sparse = os.path.join(tmp, "sparse")
    gen(sparse, 11, "duration_s=600", "turn_fraction=1", "ais_min_s=10", "ais_max_s=30", "range_sigma_m=2",
        "bearing_sigma_deg=0.3", "n_targets=15")
    reps = {}
    for accel in ("-1", "0"):
        out = os.path.join(tmp, "sparse_%s.json" % accel)
        p = run(DIAG, "multi", sparse, "--json", out, "--gate-m", "300", "--sigma-range-m", "2", "--sigma-deg", "0.3",
                "--threads", "2", "--reference-max-gap", "30", "--reference-accel", accel)
        check(p.returncode == 0, "sparse reference, --reference-accel %s: runs: %s" % (accel, p.stderr.strip()[-200:]))
        reps[accel] = json.load(open(out)) if p.returncode == 0 else None
    if reps["-1"] and reps["0"]:
        comp = {k: v for k, v in reps["-1"]["noise"].items() if "nominal_correlated_sigma" in v}
        check(comp and all(k.endswith(":range") or v["nominal_correlated_sigma"] >= 0.1 * math.radians(0.3) for k, v in comp.items())
              and all(v["nominal_correlated_sigma"] >= 0.1 * 2 for k, v in comp.items() if k.endswith(":range"))
              and all(10 <= v["nominal_correlated_tau_s"] <= 30 for v in comp.values()),
              "the interpolation's component on %d channels, e.g. %s" % (len(comp), sorted(comp.items())[:1]))
        check(not any("nominal_correlated_sigma" in v for v in reps["0"]["noise"].values()),
              "none with the reference taken as exact")
        corr = {a: sum(1 for v in r["noise"].values() if v["model"] != "white") for a, r in reps.items()}
        check(corr["-1"] < corr["0"], "channels judged correlated: %d with the interpolation's uncertainty, %d without"
              % (corr["-1"], corr["0"]))
        for a, r in reps.items():
            named = ["%s[%s]" % (e["name"], e.get("scope")) for e in mean_effects(r)]
            check(not named, "sparse reference, --reference-accel %s: no mean effect named (%s)" % (a, ", ".join(named)))

sys.exit(checks.finish())
