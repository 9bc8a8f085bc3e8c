#!/usr/bin/env python3
"""ctest outputs.uav_realizations and outputs.geometry: what a run writes besides its summary.

Usage: check_outputs.py SOURCE_DIR BUILD_DIR uav|geometry

uav: runs scripts/run uav in one process (--inproc) twice (the default sensor period 0.2 s, and
0.4 s, which does not divide the 1 s row step) and recomputes from realizations.csv alone
(loggers/uav_realizations.hpp): summary.json's RMS position and velocity error, mean NEES and
diverged count per estimator (over the at_eval rows), and uav_stats_time.csv's RMSE at 10, 60
and 150 s. Tolerances come from the printed precision: rows carry 9 significant digits (relative
rounding <= 5e-9), uav_stats_time.csv 6 decimals (<= 5e-7). A row changed by 0.1 % must be
caught, so the comparison can fail.

geometry: runs scripts/run paper (--inproc, with plots) and checks that geometry.png is drawn and
that stats_time.csv's aircraft_x_m, aircraft_y_m, aircraft_z_m (the true position in L the plot
draws) lie at the printed slant range range_m from the radar site of scenario.json, to the
rounding of the printed values: each is printed to 0.01 m (error <= 0.005 m), so the computed
distance may differ by at most 0.005 (sqrt(3) + 1) = 0.0137 m.
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

SRC, BUILD, WHAT = sys.argv[1], sys.argv[2], sys.argv[3]
SCR = os.path.join(BUILD, "test_scratch", "outputs_" + WHAT)
fails = []


def check(ok, msg):
    if not ok:
        fails.append(msg)
    return ok


def run(args):
    env = dict(os.environ, RNAV_BUILD=BUILD)
    r = subprocess.run([os.path.join(SRC, "scripts", "run")] + args, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        print(r.stdout)
        sys.exit("FAIL: scripts/run %s exited %d" % (" ".join(args), r.returncode))


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def close(a, b, tol):
    return abs(a - b) <= tol


def uav_failures(rows, summ, st, diverge_m):
    """What of summary.json / uav_stats_time.csv the rows do not reproduce (messages)."""
    out = []
    for name, e in summ["estimators"].items():
        ev = [r for r in rows if r["estimator"] == name and r["at_eval"] == "1"]
        if len(ev) != e["runs"]:
            out.append("%s: %d at_eval rows, summary says %d runs" % (name, len(ev), e["runs"]))
            continue
        pos = [float(r["pos_err_m"]) for r in ev]
        vel = [float(r["vel_err_mps"]) for r in ev]
        nees = [float(r["nees"]) for r in ev]
        for what, got in (("rmse_pos_m", math.sqrt(sum(p * p for p in pos) / len(pos))),
                          ("rmse_vel_mps", math.sqrt(sum(v * v for v in vel) / len(vel))),
                          ("nees_mean", sum(nees) / len(nees))):
            if not close(got, e[what], 1e-8 * abs(e[what]) + 1e-12):
                out.append("summary.json %s %s: %.12g, rows give %.12g" % (name, what, e[what], got))
        div = sum(1 for p in pos if not math.isfinite(p) or p > diverge_m)
        if div != e["diverged"]:
            out.append("summary.json %s diverged: %d, rows give %d" % (name, e["diverged"], div))
        for r in rows:
            if r["estimator"] != name:
                continue
            if not close(float(r["pos_err_m"]), math.hypot(float(r["pos_err_north_m"]), float(r["pos_err_east_m"])),
                         1e-8 * float(r["pos_err_m"]) + 1e-12):
                out.append("%s: pos_err_m is not the norm of its components" % name)
                break
    by_t = {round(float(s["t_s"]), 3): s for s in st}
    for t in (10.0, 60.0, 150.0):
        s = by_t.get(t)
        if s is None:
            out.append("uav_stats_time.csv: no row at t = %g s" % t)
            continue
        for name in summ["estimators"]:
            rr = [r for r in rows if r["estimator"] == name and abs(float(r["t_s"]) - t) < 1e-9]
            if len(rr) != int(s["%s_n" % name]):
                out.append("t = %g s %s: %d rows, uav_stats_time.csv n %s" % (t, name, len(rr), s["%s_n" % name]))
                continue
            rmse = math.sqrt(sum(float(r["pos_err_m"]) ** 2 for r in rr) / len(rr))
            ref = float(s["%s_rmse_pos_m" % name])
            if not close(rmse, ref, 6e-7 + 1e-8 * ref):
                out.append("uav_stats_time.csv t = %g s %s_rmse_pos_m: %.9f, rows give %.9f" % (t, name, ref, rmse))
    return out


def check_uav(period_s, n_real=6):
    out = os.path.join(SCR, "uav_%g" % period_s)
    run(["uav", "--inproc", "--no-plots", "--realizations", str(n_real), "--seed", "5",
         "--set", "sensor.period_s=%g" % period_s, "--force", "--out", out])
    rows = read_rows(os.path.join(out, "realizations.csv"))
    summ = json.load(open(os.path.join(out, "summary.json")))
    st = read_rows(os.path.join(out, "uav_stats_time.csv"))
    sc = json.load(open(os.path.join(out, "scenario.json")))
    step = sc["logger"]["realizations_step_s"]
    tag = "period %g s: " % period_s
    if not check(len(rows) > 0, tag + "realizations.csv is empty"):
        return
    check(sorted({int(r["realization"]) for r in rows}) == list(range(n_real)), tag + "realizations are not 0..%d" % (n_real - 1))
    # Off the evaluation frame, one row per estimator and step interval: the interval's first frame.
    frames = sorted({round(float(s["t_s"]), 6) for s in st})
    for name in summ["estimators"]:
        got = sorted({round(float(r["t_s"]), 6) for r in rows if r["estimator"] == name and r["at_eval"] == "0"})
        first = {}
        for t in frames:
            first.setdefault(math.floor(t / step + 1e-9), t)
        want = set(first.values())
        extra = set(got) - want
        check(not extra, tag + "%s rows at %s, not the first frame of a %g s interval" % (name, sorted(extra)[:3], step))
        missing = want - {round(float(r["t_s"]), 6) for r in rows if r["estimator"] == name}
        check(not missing, tag + "%s has no row at %s" % (name, sorted(missing)[:3]))
    for msg in uav_failures(rows, summ, st, sc["logger"]["diverge_pos_m"]):
        fails.append(tag + msg)
    bad = [dict(r) for r in rows]
    r0 = next(r for r in bad if r["at_eval"] == "1")
    r0["pos_err_m"] = repr(float(r0["pos_err_m"]) * 1.001)
    check(any("rmse_pos_m" in m for m in uav_failures(bad, summ, st, sc["logger"]["diverge_pos_m"])),
          tag + "a 0.1 % change in one row went unnoticed")


def check_geometry():
    out = os.path.join(SCR, "paper")
    run(["paper", "--inproc", "--realizations", "4", "--seed", "5", "--force", "--out", out])
    png = os.path.join(out, "geometry.png")
    check(os.path.isfile(png) and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n", "no geometry.png (a PNG) in %s" % out)
    radar = json.load(open(os.path.join(out, "scenario.json")))["radar"]
    p_R = (radar["x_m"], radar["antenna_height_m"], radar["z_m"])  # radar site in L: x, y (up), z
    worst = 0.0
    rows = read_rows(os.path.join(out, "stats_time.csv"))
    for w in rows:
        p = [float(w["aircraft_%s_m" % c]) for c in "xyz"]
        worst = max(worst, abs(math.dist(p, p_R) - float(w["range_m"])))
    check(len(rows) > 100, "stats_time.csv has %d rows" % len(rows))
    check(worst <= 0.005 * (math.sqrt(3) + 1), "aircraft position and range_m disagree by %.4f m" % worst)


if __name__ == "__main__":
    shutil.rmtree(SCR, ignore_errors=True)
    os.makedirs(SCR)
    if WHAT == "uav":
        check_uav(0.2)
        check_uav(0.4)
    elif WHAT == "geometry":
        check_geometry()
    else:
        sys.exit("check_outputs.py: unknown check %r (uav or geometry)" % WHAT)
    for f in fails:
        print("FAIL: " + f)
    print("%d failure(s)" % len(fails))
    sys.exit(1 if fails else 0)
