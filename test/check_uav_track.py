#!/usr/bin/env python3
"""ctest outputs.uav_track: the UAV run's track.csv (loggers/uav_track.hpp) and geometry.png.

Usage: check_uav_track.py SOURCE_DIR BUILD_DIR

Runs scripts/run uav --inproc --realizations 3 (with plots) three times: the default scenario
(track of realization 0), logger.track_realization=2 with sensor.max_range_m=350 (so that some
frames have no bearing), and logger.track_realization=-1; and checks:

* the truth columns are what the scenario implies: the object's position start + v t and its
  velocity (speed, heading) for the constant-velocity default, the UAV's distance from the orbit
  centre (the object's start + uav.centre_offset_*) equal to uav.radius_m, frames every
  sensor.period_s;
* the bearing: n_bearings is 1 exactly where the object is within sensor.max_range_m, 0 where it
  is not, and then bearing_rad is nan (the documented flag of a missing bearing); a measured
  bearing lies within k sigma (sensor.sigma_deg) of the true bearing from the UAV to the object,
  k chosen so that all n frames of Gaussian noise pass with probability 1 - 1e-6 (k about 6.1
  for 943 frames);
* each estimate row equals that estimator's row of realizations.csv at the same time (for every
  row realizations.csv has of the tracked realization): estimate minus truth against
  pos_err_*/vel_err_*, sqrt(P_nn), sqrt(P_ee) against sigma_pos_*; an estimate from the first
  bearing on and none before;
* the ellipse input P (P_nn, P_ne, P_ee) positive definite: both diagonals and the determinant
  above the rounding of the printed values (the file has one off-diagonal column, so the 2x2 is
  symmetric by construction);
* geometry.png exists and is a PNG of at least 800 x 600 pixels; with track_realization = -1
  neither track.csv nor geometry.png is written; track_realization = 3 of 3 realizations is
  refused naming the key (exit status 2).

Tolerances come from the printed precision alone: track.csv and realizations.csv print %.9g, a
value x is off by at most half a unit in its 9th significant digit, 0.5 * 10^(floor(log10|x|) - 8)
(hulp9 below); t_s is printed to the microsecond, which is exact (frame times are whole
microseconds). A difference of printed values may be off by the sum of their bounds; a
distance, a square root or a determinant by the bounds carried through its first-order
derivative. Double arithmetic adds ~1e-16 relative, far below these; 1e-12 * (1 + |x|) is added
for it. A self-check moves one estimate by 3 rounding bounds and requires the comparison to
catch it, so the tolerances are not vacuous.
"""
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys

SRC, BUILD = sys.argv[1], sys.argv[2]
SCR = os.path.join(BUILD, "test_scratch", "outputs_uav_track")
fails = []


def check(ok, msg):
    if not ok:
        fails.append(msg)
    return ok


def run(args, expect=0):
    env = dict(os.environ, RNAV_BUILD=BUILD)
    r = subprocess.run([os.path.join(SRC, "scripts", "run")] + args, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if r.returncode != expect:
        print(r.stdout)
        sys.exit("FAIL: scripts/run %s exited %d, expected %d" % (" ".join(args), r.returncode, expect))
    return r.stdout


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def hulp9(x):
    """Half a unit in the 9th significant digit of x: the rounding bound of %.9g."""
    if x == 0 or not math.isfinite(x):
        return 0.0
    return 0.5 * 10.0 ** (math.floor(math.log10(abs(x))) - 8)


def arith(*xs):
    return 1e-12 * (1 + sum(abs(x) for x in xs))


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def k_sigma(n, p_all=1e-6):
    """k with n * P(|z| > k) = p_all for standard normal z (bisection)."""
    lo, hi = 0.0, 20.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if n * math.erfc(mid / math.sqrt(2)) > p_all:
            lo = mid
        else:
            hi = mid
    return hi


def estimate_mismatches(track, reals, realization, names):
    """Messages for each realizations.csv row of `realization` its track row does not reproduce."""
    out = []
    by_t = {"%.3f" % float(r["t_s"]): r for r in track}
    for e in names:
        rows = [r for r in reals if r["estimator"] == e and int(r["realization"]) == realization]
        if not rows:
            out.append("realizations.csv has no row of %s, realization %d" % (e, realization))
        for rr in rows:
            tr = by_t.get(rr["t_s"])
            if tr is None:
                out.append("%s t = %s s: no track.csv row" % (e, rr["t_s"]))
                continue
            for comp, truth, err in (("north_m", "object_north_m", "pos_err_north_m"),
                                     ("east_m", "object_east_m", "pos_err_east_m"),
                                     ("v_north_mps", "object_v_north_mps", "vel_err_north_mps"),
                                     ("v_east_mps", "object_v_east_mps", "vel_err_east_mps")):
                x, y, d = float(tr["%s_%s" % (e, comp)]), float(tr[truth]), float(rr[err])
                tol = hulp9(x) + hulp9(y) + hulp9(d) + arith(x, y)
                if not abs((x - y) - d) <= tol:
                    out.append("%s t = %s s: %s - %s = %.12g, realizations.csv %s = %.12g (tolerance %.3g)"
                               % (e, rr["t_s"], comp, truth, x - y, err, d, tol))
            for P, sig in (("P_nn_m2", "sigma_pos_north_m"), ("P_ee_m2", "sigma_pos_east_m")):
                p, s = float(tr["%s_%s" % (e, P)]), float(rr[sig])
                tol = hulp9(p) / (2 * math.sqrt(p)) + hulp9(s) + arith(s) if p > 0 else 0
                if not abs(math.sqrt(p) - s) <= tol:
                    out.append("%s t = %s s: sqrt(%s) = %.12g, realizations.csv %s = %.12g"
                               % (e, rr["t_s"], P, math.sqrt(p) if p >= 0 else float("nan"), sig, s))
    return out


def check_track(out, realization, max_range_m=None):
    tag = "%s: " % os.path.basename(out)
    sc = json.load(open(os.path.join(out, "scenario.json")))
    track = read_rows(os.path.join(out, "track.csv"))
    reals = read_rows(os.path.join(out, "realizations.csv"))
    if not check(len(track) > 100, tag + "track.csv has %d rows" % len(track)):
        return
    header = list(track[0].keys())
    names = [h[:-len("_P_nn_m2")] for h in header if h.endswith("_P_nn_m2")]
    check(sorted(names) == ["ekf", "rpekf"], tag + "estimators in track.csv: %s" % names)
    check(all(int(r["realization"]) == realization for r in track), tag + "realization column is not %d" % realization)
    tg, uav, sen = sc["target"], sc["uav"], sc["sensor"]
    check(not tg["manoeuvres"] and uav["path"] == "circle", tag + "the checks below assume the default scenario")

    # Frames: every sensor.period_s from 0 over the duration; t_s exact to the microsecond.
    ts = [float(r["t_s"]) for r in track]
    check(all(abs(t - k * sen["period_s"]) <= 1e-9 for k, t in enumerate(ts)),
          tag + "frames are not every sensor.period_s = %g s from 0" % sen["period_s"])
    check(sc["duration_s"] - sen["period_s"] < ts[-1] <= sc["duration_s"],
          tag + "last frame at %g s, the run lasts %g s" % (ts[-1], sc["duration_s"]))

    # The object: constant velocity from its start.
    h = math.radians(tg["heading_deg"])
    vn, ve = tg["speed_mps"] * math.cos(h), tg["speed_mps"] * math.sin(h)
    worst = {}
    for r, t in zip(track, ts):
        for col, want in (("object_north_m", tg["start_north_m"] + vn * t), ("object_east_m", tg["start_east_m"] + ve * t),
                          ("object_v_north_mps", vn), ("object_v_east_mps", ve)):
            got = float(r[col])
            if not abs(got - want) <= hulp9(got) + arith(want):
                worst.setdefault(col, (t, got, want))
    for col, (t, got, want) in worst.items():
        fails.append(tag + "%s at t = %g s: %.12g, the scenario gives %.12g" % (col, t, got, want))

    # The UAV on its circle about the object's start + offset.
    cn = tg["start_north_m"] + uav["centre_offset_north_m"]
    ce = tg["start_east_m"] + uav["centre_offset_east_m"]
    bad = []
    for r, t in zip(track, ts):
        n, e = float(r["uav_north_m"]), float(r["uav_east_m"])
        d = math.hypot(n - cn, e - ce)
        if not abs(d - uav["radius_m"]) <= hulp9(n) + hulp9(e) + arith(n, e, cn, ce):
            bad.append((t, d))
    check(not bad, tag + "UAV off its circle of %g m: %s" % (uav["radius_m"], bad[:3]))

    # Bearings: present exactly within range, nan when missing, within k sigma of the truth.
    rng_max = sen["max_range_m"] if max_range_m is None else max_range_m
    sigma = math.radians(sen["sigma_deg"])
    have = [r for r in track if int(r["n_bearings"]) > 0]
    k = k_sigma(max(1, len(have)))
    n_missing = 0
    for r, t in zip(track, ts):
        on, oe, un, ue = (float(r[c]) for c in ("object_north_m", "object_east_m", "uav_north_m", "uav_east_m"))
        rng = math.hypot(on - un, oe - ue)
        tol = hulp9(on) + hulp9(oe) + hulp9(un) + hulp9(ue)
        nb, b = int(r["n_bearings"]), float(r["bearing_rad"])
        if rng > rng_max + tol:
            n_missing += 1
            check(nb == 0 and math.isnan(b) and r["bearing_rad"] == "nan",
                  tag + "t = %g s: object at %.3f m > max range %g m, yet n_bearings %d, bearing_rad %s"
                  % (t, rng, rng_max, nb, r["bearing_rad"]))
        elif rng < rng_max - tol:
            if check(nb == 1 and math.isfinite(b), tag + "t = %g s: no bearing within range" % t):
                dev = wrap(b - math.atan2(oe - ue, on - un))
                check(abs(dev) <= k * sigma, tag + "t = %g s: bearing %.6f rad is %.2f sigma from the truth (k = %.2f)"
                      % (t, b, dev / sigma, k))
    if max_range_m is not None:
        check(0 < n_missing < len(track), tag + "%d of %d frames without a bearing: the case tests nothing"
              % (n_missing, len(track)))

    # Estimates: none before the first bearing, one at every frame from it on.
    first = next(i for i, r in enumerate(track) if int(r["n_bearings"]) > 0)
    for e in names:
        est = [math.isfinite(float(r[e + "_north_m"])) for r in track]
        check(est == [i >= first for i in range(len(track))],
              tag + "%s: estimates are not exactly the frames from the first bearing (t = %g s) on" % (e, ts[first]))
    for m in estimate_mismatches(track, reals, realization, names)[:10]:
        fails.append(tag + m)

    # The ellipse input: positive definite beyond the rounding of the printed P.
    not_pd = []
    for r, t in zip(track, ts):
        for e in names:
            a, b, d = (float(r["%s_P_%s_m2" % (e, c)]) for c in ("nn", "ne", "ee"))
            if math.isnan(a):
                continue
            ha, hb, hd = hulp9(a), hulp9(b), hulp9(d)
            det = a * d - b * b
            det_tol = abs(d) * ha + abs(a) * hd + 2 * abs(b) * hb + ha * hd + hb * hb + arith(a * d, b * b)
            if not (a > ha and d > hd and det > det_tol):
                not_pd.append((e, t, a, b, d))
    check(not not_pd, tag + "P not positive definite: %s" % not_pd[:3])

    # The comparison must be able to fail: one estimate moved by 3 rounding bounds.
    moved = [dict(r) for r in track]
    r0 = next(r for r in moved if float(r["t_s"]) >= 60 and float(r["t_s"]).is_integer())  # has a realizations.csv row
    x = float(r0["rpekf_north_m"])
    r0["rpekf_north_m"] = repr(x + 3 * (2 * hulp9(x) + hulp9(float(r0["object_north_m"]))))
    check(any("rpekf" in m and "north_m" in m for m in estimate_mismatches(moved, reals, realization, ["rpekf"])),
          tag + "an estimate moved by 3 rounding bounds went unnoticed")

    png = os.path.join(out, "geometry.png")
    ok = check(os.path.isfile(png), tag + "no geometry.png")
    if ok:
        head = open(png, "rb").read(24)
        if check(head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR", tag + "geometry.png is not a PNG"):
            w, hgt = struct.unpack(">II", head[16:24])
            check(w >= 800 and hgt >= 600, tag + "geometry.png is %d x %d pixels" % (w, hgt))


if __name__ == "__main__":
    shutil.rmtree(SCR, ignore_errors=True)
    os.makedirs(SCR)
    base = ["uav", "--inproc", "--realizations", "3", "--seed", "5", "--force"]
    a = os.path.join(SCR, "default")
    run(base + ["--out", a])
    check_track(a, 0)
    b = os.path.join(SCR, "r2_range350")
    run(base + ["--set", "logger.track_realization=2", "--set", "sensor.max_range_m=350", "--out", b])
    check_track(b, 2, max_range_m=350)
    c = os.path.join(SCR, "none")
    run(base + ["--set", "logger.track_realization=-1", "--out", c])
    check(not os.path.exists(os.path.join(c, "track.csv")), "track_realization = -1 wrote track.csv")
    check(not os.path.exists(os.path.join(c, "geometry.png")), "track_realization = -1 drew geometry.png")
    msg = run(base + ["--set", "logger.track_realization=3", "--out", os.path.join(SCR, "bad")], expect=2)
    check("logger.track_realization" in msg, "track_realization = 3 of 3: the error does not name the key: " + msg)
    for f in fails:
        print("FAIL: " + f)
    print("%d failure(s)" % len(fails))
    sys.exit(1 if fails else 0)
