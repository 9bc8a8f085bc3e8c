#!/usr/bin/env python3
"""Checks of scripts/flightgen.py, the independent flight generator.

Usage: check_flightgen.py SOURCE_DIR

1. Determinism: the same seed and keys (with every kind of noise on) give byte-identical files,
   through the CLI into two folders; another seed changes every data file; changing only a
   noise key leaves truth.csv as it was (separate random streams).
2. Geodesy: geodetic -> ECEF -> geodetic within 1e-9 deg and 1 mm for random points, h up to
   10 km, |lat| up to 89 and the poles; ECEF equal to this file's own formula within 1e-6 m.
3. With all noise zero and no effects every plot equals the true polar coordinates this file
   computes itself (its own WGS84 and ENU) from the truth: within 1e-6 m / 1e-9 deg from the
   returned (unrounded) rows, within the printed precision from the files; a plot exists exactly
   where the truth is in the field of view. With time_offset_s = 1 (and 0.55) a plot stamped t
   equals the truth at t - tau (linearly interpolated here) within 0.5 m. The same for the UAV's
   bearings (observer nav error zero).
4. Bad input: an unknown key (the nearest one named), NaN, inf, out of range, a non-integer count,
   an unknown choice or mode: exit status 2, one line "flightgen.py: error: ..." naming key and value,
   no output folder created.
5. The default intercept flight (seeds 1-5): horizontal speed 80 m/s at the start and 65 m/s at the
   end within 1 m/s, a track change over 15 deg, 350-650 plots.
Tolerances from the printed precision: lat/lon %.9f deg (0.5e-9 deg = 5.6e-5 m per axis), heights
and ranges %.4f m, angles %.8f deg; half a unit of the last digit each, carried to range and angles
to first order.
"""
import json
import math
import os
import random
import subprocess
import sys
import tempfile

SRC = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
GEN = os.path.join(SRC, "scripts", "flightgen.py")
sys.path.insert(0, os.path.join(SRC, "scripts"))
import flightgen  # noqa: E402

A, F = 6378137.0, 1 / 298.257223563
B = A * (1 - F)
FAILS = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        FAILS.append(what)


# ---- this file's own geodesy (independent of the generator's)
def ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A * A / math.sqrt((A * math.cos(la)) ** 2 + (B * math.sin(la)) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (B / A) ** 2 + h) * math.sin(la))


def enu(lat0, lon0, h0, p):
    la, lo = math.radians(lat0), math.radians(lon0)
    o = ecef(lat0, lon0, h0)
    dx, dy, dz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
    e = -math.sin(lo) * dx + math.cos(lo) * dy
    t = math.cos(lo) * dx + math.sin(lo) * dy
    return e, -math.sin(la) * t + math.cos(la) * dz, math.cos(la) * t + math.sin(la) * dz


def radar_polar(site, p):
    """(range m, azimuth deg from the reference, elevation deg, horizontal distance m)."""
    e, n, u = enu(site["lat_deg"], site["lon_deg"], site["h_m"], p)
    az = (math.degrees(math.atan2(e, n)) - site["azimuth_reference_deg"] + 540.0) % 360.0 - 180.0
    return math.sqrt(e * e + n * n + u * u), az, math.degrees(math.atan2(u, math.hypot(e, n))), math.hypot(e, n)


def dang(a, b):
    return abs((a - b + 540.0) % 360.0 - 180.0)


def read_csv(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0].split(","), [[float(x) for x in ln.split(",")] for ln in lines[1:]]


def run(*args):
    return subprocess.run([sys.executable, GEN] + list(args), capture_output=True, text=True)


def lerp(rows, t):
    """ECEF of the truth (t, lat, lon, h) rows at 10 Hz, linearly interpolated at t."""
    i = min(int(math.floor(t * 10 + 1e-9)), len(rows) - 2)
    w = t * 10 - i
    p, q = ecef(*rows[i][1:4]), ecef(*rows[i + 1][1:4])
    return tuple(a + w * (b - a) for a, b in zip(p, q))


# ---- 1
def check_determinism(tmp):
    effects = ["--set", "coloured_tau_s=20", "--set", "coloured_kind=cascade", "--set", "outlier_prob=0.05",
               "--set", "time_offset_s=0.3", "--set", "step_size=0.2", "--set", "range_drift_mps=0.05"]
    for mode, extra, files in (("landing", effects, ("site.json", "radar.csv", "nav.csv", "truth.csv")),
                               ("uav", ["--set", "coloured_tau_s=15", "--set", "outlier_prob=0.05"],
                                ("observer.csv", "bearings.csv", "truth.csv"))):
        outs = {}
        for tag, seed in (("a", "11"), ("b", "11"), ("c", "12")):
            d = os.path.join(tmp, "det_%s_%s" % (mode, tag))
            r = run(mode, d, "--seed", seed, *extra)
            check(r.returncode == 0, "determinism: %s seed %s runs%s" % (mode, seed, r.stderr.strip() and ": " + r.stderr.strip()))
            outs[tag] = {f: open(os.path.join(d, f), "rb").read() for f in files}
        same = all(outs["a"][f] == outs["b"][f] for f in files)
        check(same, "determinism: %s: same seed and keys give byte-identical %s" % (mode, ", ".join(files)))
        differ = [f for f in files if outs["a"][f] != outs["c"][f]]
        check(len(differ) == len(files), "determinism: %s: another seed changes %s" % (mode, ", ".join(differ)))
    a = flightgen.landing(os.path.join(tmp, "s1"), 3, {})
    b = flightgen.landing(os.path.join(tmp, "s2"), 3, {"sigma_range_m": 30, "outlier_prob": 0.1, "coloured_tau_s": 5})
    check(a["truth"] == b["truth"] and a["plots"] != b["plots"],
          "determinism: changing noise keys leaves the truth as it was and changes the plots")
    for mode, data in (("landing", "plots"), ("uav", "bearings")):
        fn = getattr(flightgen, mode)
        a = fn(os.path.join(tmp, "n1"), 5, {})
        b = fn(os.path.join(tmp, "n2"), 5, {}, noise_seed=5)
        c = fn(os.path.join(tmp, "n3"), 5, {}, noise_seed=6)
        check(a[data] == b[data] and a["truth"] == c["truth"] and a[data] != c[data],
              "determinism: %s: noise_seed defaults to the seed; another one keeps the truth and changes the %s"
              % (mode, data))


# ---- 2
def check_geodesy():
    rng = random.Random(7)
    pts = [(0.0, 0.0, 0.0), (90.0, 0.0, 0.0), (-90.0, 45.0, 10000.0), (89.0, 10.0, 10000.0), (-89.0, -170.0, 0.0)]
    pts += [(rng.uniform(-89, 89), rng.uniform(-180, 180), rng.choice([0.0, 10000.0, rng.uniform(-400, 10000)]))
            for _ in range(3000)]
    pts += [(s * rng.uniform(88, 89), rng.uniform(-180, 180), rng.uniform(0, 10000)) for s in (-1, 1) for _ in range(200)]
    worst = [0.0, 0.0, 0.0, 0.0]
    for lat, lon, h in pts:
        p = flightgen.to_ecef(lat, lon, h)
        q = ecef(lat, lon, h)
        lat2, lon2, h2 = flightgen.to_geodetic(*p)
        dlon = 0.0 if abs(lat) == 90 else dang(lon, lon2)
        worst = [max(worst[0], abs(lat - lat2)), max(worst[1], dlon), max(worst[2], abs(h - h2)),
                 max(worst[3], math.dist(p, q))]
    check(worst[0] < 1e-9 and worst[1] < 1e-9 and worst[2] < 1e-3,
          "geodesy: round trip of %d points: max |dlat| %.2e deg, |dlon| %.2e deg, |dh| %.2e m" % (len(pts), *worst[:3]))
    check(worst[3] < 1e-6, "geodesy: ECEF against this file's formula: max %.2e m" % worst[3])
    check(math.dist(flightgen.to_ecef(90, 0, 0), (0, 0, B)) < 1e-6 and math.dist(flightgen.to_ecef(0, 0, 0), (A, 0, 0)) < 1e-9,
          "geodesy: pole at (0, 0, b), equator/Greenwich at (a, 0, 0)")


# ---- 3
ZERO = {"sigma_range_m": 0, "sigma_az_deg": 0, "sigma_el_deg": 0, "nav_sigma_m": 0, "nav_white_m": 0}


def in_fov(pol):
    return abs(pol[1]) < 60 and 0.1 <= pol[2] <= 30


def check_polar(tmp):
    for seed, geo in ((5, "intercept"), (6, "level"), (7, "turns"), (8, "straight")):
        res = flightgen.landing(os.path.join(tmp, "z%d" % seed), seed, dict(ZERO, geometry=geo))
        P, truth, plots = res["params"], res["truth"], res["plots"]
        site = dict(lat_deg=P["radar_lat_deg"], lon_deg=P["radar_lon_deg"], h_m=P["radar_h_m"],
                    azimuth_reference_deg=P["azimuth_reference_deg"])
        worst, times = [0.0, 0.0, 0.0], set()
        for t, r, az, el in plots:
            pol = radar_polar(site, ecef(*truth[round(t * 10)][1:4]))
            worst = [max(worst[0], abs(r - pol[0])), max(worst[1], dang(az, pol[1])), max(worst[2], abs(el - pol[2]))]
            times.add(round(t))
        check(worst[0] < 1e-6 and worst[1] < 1e-9 and worst[2] < 1e-9,
              "polar %s seed %d: %d plots = truth's polar coordinates (rows): max %.1e m, %.1e deg, %.1e deg"
              % (geo, seed, len(plots), *worst))
        expect = {round(row[0]) for row in truth if abs(row[0] - round(row[0])) < 1e-9 and in_fov(radar_polar(site, ecef(*row[1:4])))}
        check(expect == times, "polar %s seed %d: plots exactly where the truth is in the field of view (%d)" % (geo, seed, len(expect)))
        check_polar_files(os.path.join(tmp, "z%d" % seed), "%s seed %d" % (geo, seed))
    for tau in (1.0, 0.55, -0.3):
        res = flightgen.landing(os.path.join(tmp, "tau"), 5, dict(ZERO, time_offset_s=tau))
        P, truth = res["params"], res["truth"]
        site = dict(lat_deg=P["radar_lat_deg"], lon_deg=P["radar_lon_deg"], h_m=P["radar_h_m"],
                    azimuth_reference_deg=P["azimuth_reference_deg"])
        worst = 0.0
        for t, r, az, el in res["plots"]:
            pol = radar_polar(site, lerp(truth, t - tau))
            worst = max(worst, abs(r - pol[0]), r * math.radians(dang(az, pol[1])), r * math.radians(abs(el - pol[2])))
        check(worst < 0.5 and len(res["plots"]) > 300,
              "time offset %g s: %d plots stamped t = truth at t - tau within %.2e m (bound 0.5 m)" % (tau, len(res["plots"]), worst))


def check_polar_files(d, what):
    site = json.load(open(os.path.join(d, "site.json")))["radar"]
    _, truth = read_csv(os.path.join(d, "truth.csv"))
    hdr, plots = read_csv(os.path.join(d, "radar.csv"))
    dp = math.sqrt(2 * (0.5e-9 * math.pi / 180 * 6.4e6) ** 2 + 0.5e-4 ** 2)
    bad = 0
    for t, r, az, el in plots:
        pol = radar_polar(site, ecef(*truth[round(t * 10)][1:4]))
        tol_ang = 0.5e-8 + math.degrees(dp / pol[3]) + 1e-9
        bad += abs(r - pol[0]) > 0.5e-4 + dp + 1e-6 or dang(az, pol[1]) > tol_ang or abs(el - pol[2]) > tol_ang
    check(hdr == ["t_s", "range_m", "azimuth_deg", "elevation_deg"] and bad == 0,
          "polar %s: radar.csv against truth.csv and site.json within the printed precision (%d rows off)" % (what, bad))


def check_uav_bearings(tmp):
    for geo in ("orbit", "racetrack", "figure8"):
        for tau in (0.7, 0.0):   # the files checked below are tau = 0's
            d = os.path.join(tmp, "u_%s" % geo)
            res = flightgen.uav(d, 9, {"geometry": geo, "sigma_deg": 0, "obs_nav_sigma_m": 0, "time_offset_s": tau})
            obs, boat = res["observer_truth"], [(t, la, lo, 0.0) for t, la, lo in res["truth"]]
            worst = 0.0
            for t, b in res["bearings"]:
                po, pb = lerp(obs, t - tau), lerp(boat, t - tau)
                lat, lon, h = flightgen.to_geodetic(*po)   # the observer's geodetic position; its ENU is this file's
                e, n, _ = enu(lat, lon, h, pb)
                worst = max(worst, dang(b, math.degrees(math.atan2(e, n))))
            tol = 1e-9 if tau == 0 else 0.5 / 300     # rows: exact; interpolated: 0.5 m at >= 300 m
            expect = sum(1 for k in range(601) if 0 <= k / 2 - tau <= 300)
            check(worst < tol and len(res["bearings"]) == expect,
                  "uav %s, tau %g s: %d bearings = true bearing (own ENU) within %.1e deg"
                  % (geo, tau, len(res["bearings"]), worst))
        _, ob = read_csv(os.path.join(d, "observer.csv"))
        _, tr = read_csv(os.path.join(d, "truth.csv"))
        _, br = read_csv(os.path.join(d, "bearings.csv"))
        worst = 0.0
        for t, b in br[:: 7]:
            k = round(t * 10)
            e, n, _ = enu(ob[k][1], ob[k][2], ob[k][3], ecef(tr[k][1], tr[k][2], 0.0))
            worst = max(worst, dang(b, math.degrees(math.atan2(e, n))) * math.radians(1) * math.hypot(e, n))
        check(worst < 1e-3, "uav %s files: bearings.csv against observer.csv and truth.csv: max %.1e m across the line of sight"
              % (geo, worst))


# ---- 4
def check_bad_input(tmp):
    d = os.path.join(tmp, "bad")
    cases = [(("landing", d, "--set", "sped0_mps=70"), ("sped0_mps", "speed0_mps")),
             (("landing", d, "--set", "sigma_range_m=nan"), ("sigma_range_m", "nan")),
             (("landing", d, "--set", "sigma_az_deg=inf"), ("sigma_az_deg", "inf")),
             (("landing", d, "--set", "glide_deg=50"), ("glide_deg", "50")),
             (("landing", d, "--set", "rate_hz=fast"), ("rate_hz", "fast")),
             (("landing", d, "--set", "n_turns=2.5"), ("n_turns", "2.5")),
             (("landing", d, "--set", "geometry=strait"), ("geometry", "strait", "straight")),
             (("landing", d, "--set", "glide_deg=3", "--set", "glide_deg=4"), ("glide_deg", "twice")),
             (("uav", d, "--set", "sigma_deg=-1"), ("sigma_deg", "-1")),
             (("uav", d, "--set", "radius=900"), ("radius", "radius_m")),
             (("landng", d), ("landng", "landing")),
             (("landing", d, "--seed", "x"), ("--seed", "x"))]
    for args, words in cases:
        r = run(*args)
        err = r.stderr.strip()
        ok = (r.returncode == 2 and err.startswith("flightgen.py: error:") and "\n" not in err
              and all(w in err for w in words) and not os.path.exists(d))
        check(ok, "bad input %s: exit %d, %r" % (" ".join(args[2:]) or args[0], r.returncode, err))
    for mode in ("landing", "uav"):
        r = run(mode, "--list-keys")
        names = [ln.split()[0] for ln in r.stdout.splitlines()]
        check(r.returncode == 0 and names == list(flightgen.KEYS[mode]) and len(names) > 20,
              "--list-keys %s: %d keys, each with default, range and unit" % (mode, len(names)))


# ---- 5
def check_intercept(tmp):
    for seed in range(1, 6):
        d = os.path.join(tmp, "i%d" % seed)
        r = run("landing", d, "--seed", str(seed))
        _, truth = read_csv(os.path.join(d, "truth.csv"))
        _, plots = read_csv(os.path.join(d, "radar.csv"))

        def vel(i):   # horizontal velocity over 1 s in the local ENU at sample i
            e, n, _ = enu(truth[i][1], truth[i][2], truth[i][3], ecef(*truth[i + 10][1:4]))
            return math.hypot(e, n), math.degrees(math.atan2(e, n))
        (v0, c0), (v1, c1) = vel(0), vel(len(truth) - 11)
        check(r.returncode == 0 and abs(v0 - 80) < 1 and abs(v1 - 65) < 1 and dang(c0, c1) > 15 and 350 <= len(plots) <= 650,
              "intercept seed %d: speed %.2f -> %.2f m/s, track change %.1f deg, %d plots, %.1f s"
              % (seed, v0, v1, dang(c0, c1), len(plots), truth[-1][0]))


def main():
    with tempfile.TemporaryDirectory() as tmp:
        check_determinism(tmp)
        check_geodesy()
        check_polar(tmp)
        check_uav_bearings(tmp)
        check_bad_input(tmp)
        check_intercept(tmp)
    print("%d failure(s)" % len(FAILS) if FAILS else "all checks passed")
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
