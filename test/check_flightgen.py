#!/usr/bin/env python3
"""Checks of scripts/flightgen.py, the independent flight generator.

Usage: PYTHONPATH=SOURCE_DIR/scripts check_flightgen.py SOURCE_DIR (ctest sets PYTHONPATH)

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
6. Ship radar (shipradar, 300-600 s runs): the folder's headers (truth.csv without h_m), sensor
   radar, bearings in [0, 360), rows in t_s order. With no noise, p_detect 1 and a dense AIS
   (0.5 s), every detection equals the nearest target's range and bearing at its stamp, computed
   here from observer.csv and truth.csv (linear interpolation, this file's WGS84 and ENU) within
   0.5 m / 0.01 deg; every target well inside [min_range_m, max_range_m] at a scan's middle is
   detected in that scan, none well outside. stamp = scan: the same detections, each stamped at its
   sweep's end, latency = ((beta0 - beta) mod 360)/omega in [0, P] (correlation with the bearing
   -1), time_offset_s added. Effects (range gain and bias, bearing bias) applied as documented;
   ais_time_offset_s shifts the reference, ais_sigma_m adds its noise and leaves the detections.
   Defaults (600 s): detections = p_detect x the illuminations in range (binomial), AIS intervals
   in [ais_min_s, ais_max_s], ids 1..n_targets, own ship and target speeds within their bounds.
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

import flightgen

SRC = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
GEN = os.path.join(SRC, "scripts", "flightgen.py")

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
                                ("observer.csv", "bearings.csv", "truth.csv")),
                               ("shipradar", ["--set", "duration_s=300", "--set", "clutter_per_scan=2",
                                              "--set", "ais_sigma_m=5", "--set", "stamp=scan"],
                                ("observer.csv", "detections.csv", "truth.csv"))):
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
    kw = {"duration_s": 300, "n_targets": 10}
    a = flightgen.shipradar(os.path.join(tmp, "n1"), 5, kw)
    b = flightgen.shipradar(os.path.join(tmp, "n2"), 5, kw, noise_seed=5)
    c = flightgen.shipradar(os.path.join(tmp, "n3"), 5, kw, noise_seed=6)
    d = flightgen.shipradar(os.path.join(tmp, "n4"), 5, dict(kw, n_targets=12))
    check(a["detections"] == b["detections"] and a["truth"] == c["truth"] and a["observer"] == c["observer"]
          and a["detections"] != c["detections"] and a["targets"] == d["targets"][:10],
          "determinism: shipradar: noise_seed defaults to the seed; another one keeps the truth and changes the "
          "detections; more targets keep the first ones")


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
             (("landing", d, "--seed", "x"), ("--seed", "x")),
             (("shipradar", d, "--set", "stamp=scn"), ("stamp", "scn", "scan")),
             (("shipradar", d, "--set", "scan_period=3"), ("scan_period", "scan_period_s")),
             (("shipradar", d, "--set", "ais_min_s=12"), ("ais_min_s", "ais_max_s")),
             (("shipradar", d, "--set", "n_targets=201"), ("n_targets", "201")),
             (("shiprader", d), ("shiprader", "shipradar"))]
    for args, words in cases:
        r = run(*args)
        err = r.stderr.strip()
        ok = (r.returncode == 2 and err.startswith("flightgen.py: error:") and "\n" not in err
              and all(w in err for w in words) and not os.path.exists(d))
        check(ok, "bad input %s: exit %d, %r" % (" ".join(args[2:]) or args[0], r.returncode, err))
    for mode in ("landing", "uav", "shipradar"):
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


# ---- 6
def read_multi(d):
    """(observer rows, detection rows (t, range, bearing), {target: [(t, lat, lon)]}, headers, sensors)."""
    hdr_o, obs = read_csv(os.path.join(d, "observer.csv"))
    with open(os.path.join(d, "detections.csv")) as f:
        lines = f.read().splitlines()
    cells = [ln.split(",") for ln in lines[1:]]
    dets = [(float(c[0]), float(c[2]), float(c[3])) for c in cells]
    hdr_t, tr = read_csv(os.path.join(d, "truth.csv"))
    truth = {}
    for t, i, la, lo in tr:
        truth.setdefault(int(i), []).append((t, la, lo))
    return obs, dets, truth, (hdr_o, lines[0].split(","), hdr_t), {c[1] for c in cells}


def at_time(rows, t):
    """Row values (after the time) linearly interpolated at t (extrapolated from the end pairs)."""
    lo, hi = 0, len(rows) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if rows[mid][0] <= t:
            lo = mid
        else:
            hi = mid
    w = (t - rows[lo][0]) / (rows[hi][0] - rows[lo][0])
    return [a + w * (b - a) for a, b in zip(rows[lo][1:], rows[hi][1:])]


def ship_look(obs, rows, t):
    """(range m, bearing deg in [0, 360)) from the antenna (observer.csv) to a target (truth rows) at t."""
    la, lo, h = at_time(obs, t)[:3]
    e, n, u = enu(la, lo, h, ecef(*at_time(rows, t), 0.0))
    return math.sqrt(e * e + n * n + u * u), math.degrees(math.atan2(e, n)) % 360.0


def check_ship_geometry(tmp):
    P_S, B0 = 2.5, 90.0
    base = {"duration_s": 300, "n_targets": 20, "range_sigma_m": 0, "bearing_sigma_deg": 0, "p_detect": 1,
            "max_range_m": 8000, "ais_min_s": 0.5, "ais_max_s": 0.5, "scan_start_bearing_deg": B0}
    d0 = os.path.join(tmp, "ship0")
    flightgen.shipradar(d0, 4, base)
    obs, dets, truth, hdrs, sensors = read_multi(d0)
    check(hdrs == (["t_s", "lat_deg", "lon_deg", "h_m", "heading_deg"], ["t_s", "sensor", "range_m", "bearing_deg"],
                   ["t_s", "target", "lat_deg", "lon_deg"]) and sensors == {"radar"},
          "shipradar: headers %s | %s | %s (truth.csv without h_m), sensor %s" % tuple(",".join(h) for h in hdrs + (sensors,)))
    worst, hits = [0.0, 0.0], {}
    for t, r, b in dets:
        best = None
        for i, rows in truth.items():
            r2, b2 = ship_look(obs, rows, t)
            err = max(abs(r - r2) / 0.5, dang(b, b2) / 0.01)
            if best is None or err < best[0]:
                best = (err, i, abs(r - r2), dang(b, b2))
        worst = [max(worst[0], best[2]), max(worst[1], best[3])]
        hits.setdefault((best[1], int(t // P_S)), []).append(t)
    check(len(dets) > 500 and worst[0] < 0.5 and worst[1] < 0.01,
          "shipradar noise-free: %d detections = nearest target's range and bearing at the stamp (own geodesy): "
          "max %.1e m, %.1e deg (bounds 0.5 m, 0.01 deg)" % (len(dets), *worst))
    inside = outside = missed = extra = 0
    for i, rows in truth.items():
        for k in range(int(300 / P_S)):
            r = ship_look(obs, rows, (k + 0.5) * P_S)[0]
            if 50 + 150 <= r <= 8000 - 150:
                inside += 1
                missed += (i, k) not in hits
            elif r > 8000 + 150 or r < 50 - 150:
                outside += 1
                extra += (i, k) in hits
    check(inside > 300 and outside > 100 and missed == 0 and extra == 0,
          "shipradar noise-free, p_detect 1: %d target-scans well in range, %d missed; %d well out of range, %d detected"
          % (inside, missed, outside, extra))
    # stamp = scan: the same detections at the sweep's end (+ time_offset_s)
    d1 = os.path.join(tmp, "ship1")
    flightgen.shipradar(d1, 4, dict(base, stamp="scan", time_offset_s=1.5))
    _, dets_s, _, _, _ = read_multi(d1)
    by_val = {(r, b): t for t, r, b in dets}
    om = 360.0 / P_S
    lat, pred, brg, bad = [], [], [], 0
    for t, r, b in dets_s:
        ti = by_val.get((r, b))
        if ti is None:
            bad += 1
            continue
        k = round((t - 1.5) / P_S) - 1
        bad += abs(t - 1.5 - (k + 1) * P_S) > 1e-6 or not k * P_S <= ti < (k + 1) * P_S + 1e-6
        lat.append(t - 1.5 - ti)
        pred.append(((B0 - b) % 360.0) / om)
        brg.append((b - B0) % 360.0)
    if len(lat) < 100:   # nothing to compare: fail below
        lat, pred, brg = [-1.0, 0.0], [0.0, 0.0], [0.0, 1.0]
    dev = max(abs((x - y + P_S / 2) % P_S - P_S / 2) for x, y in zip(lat, pred))
    n = len(lat)
    ml, mb = sum(lat) / n, sum(brg) / n
    corr = sum((x - ml) * (y - mb) for x, y in zip(lat, brg)) / math.sqrt(
        sum((x - ml) ** 2 for x in lat) * sum((y - mb) ** 2 for y in brg) or 1.0)
    spread = (max(lat) - min(lat)) - (max(brg) - min(brg)) / om
    check(len(dets_s) == len(dets) and bad == 0 and dev < 5e-6 and min(lat) > -1e-6 and max(lat) <= P_S + 1e-6
          and max(lat) - min(lat) > 0.5 * P_S and abs(spread) < 1e-4 and corr < -0.999,
          "shipradar stamp=scan: %d detections at the sweep's end + 1.5 s (%d off); latency in [%.4f, %.4f] s = "
          "((beta0 - beta) mod 360)/omega within %.1e s; correlation with the bearing %.6f"
          % (len(dets_s), bad, min(lat), max(lat), dev, corr))
    # effects
    d2 = os.path.join(tmp, "ship2")
    flightgen.shipradar(d2, 4, dict(base, range_gain=0.01, range_bias_m=20, bearing_bias_deg=1.5, time_offset_s=-0.4))
    _, dets_e, _, _, _ = read_multi(d2)
    worst = max([0.0] + [abs(t2 - t - -0.4) for (t, _, _), (t2, _, _) in zip(dets, dets_e)]
                + [abs(r2 - (1.01 * r + 20)) for (_, r, _), (_, r2, _) in zip(dets, dets_e)]
                + [dang(b2, b + 1.5) for (_, _, b), (_, _, b2) in zip(dets, dets_e)])
    check(len(dets_e) == len(dets) > 500 and worst < 1e-3,
          "shipradar effects: t + time_offset_s, (1 + g) r + range_bias_m, bearing + bearing_bias_deg: max %.1e" % worst)
    # AIS reference: time offset and noise
    d3 = os.path.join(tmp, "ship3")
    flightgen.shipradar(d3, 4, dict(base, ais_time_offset_s=1.3))
    _, _, truth_o, _, _ = read_multi(d3)
    worst = 0.0
    for i, rows in truth_o.items():
        for t, la, lo in rows[10:-10:5]:
            worst = max(worst, math.dist(ecef(la, lo, 0.0), ecef(*at_time(truth[i], t - 1.3), 0.0)))
    check(worst < 0.05, "shipradar ais_time_offset_s 1.3: a report stamped t = the target at t - 1.3 within %.1e m" % worst)
    d4 = os.path.join(tmp, "ship4")
    flightgen.shipradar(d4, 4, dict(base, ais_sigma_m=10))
    _, dets_n, truth_n, _, _ = read_multi(d4)
    sq, m = 0.0, 0
    for i, rows in truth_n.items():
        for (t, la, lo), (t0, la0, lo0) in zip(rows, truth[i]):
            e, n, _ = enu(la0, lo0, 0.0, ecef(la, lo, 0.0))
            sq, m = sq + e * e + n * n, m + 2
    sd = math.sqrt(sq / m)
    check(9 < sd < 11 and dets_n == dets, "shipradar ais_sigma_m 10: AIS noise %.2f m per axis; detections unchanged" % sd)


def check_ship_defaults(tmp):
    d = os.path.join(tmp, "shipdef")
    r = run("shipradar", d, "--seed", "3", "--set", "duration_s=600")
    P = json.loads(r.stdout)
    obs, dets, truth, _, _ = read_multi(d)
    per, T = P["scan_period_s"], 600
    pairs = 0
    for i, rows in truth.items():
        for k in range(int(T / per)):
            # the illumination of scan k at its bearing (one iteration is enough at this accuracy)
            tk = k * per + ((ship_look(obs, rows, (k + 0.5) * per)[1] - P["scan_start_bearing_deg"]) % 360.0) / (360.0 / per)
            rr = ship_look(obs, rows, tk)[0]
            pairs += P["min_range_m"] <= rr <= P["max_range_m"]
    exp = P["p_detect"] * pairs
    tol = 5 * math.sqrt(pairs * P["p_detect"] * (1 - P["p_detect"])) + 0.01 * pairs
    check(r.returncode == 0 and abs(len(dets) - exp) < tol and 3500 < len(dets) < 8700,
          "shipradar defaults (600 s, seed 3): %d detections, expected %.0f +- %.0f (p_detect x %d target-scans in range)"
          % (len(dets), exp, tol, pairs))
    ts = [t for t, _, _ in dets]
    check(all(a <= b for a, b in zip(ts, ts[1:])) and all(0 <= b < 360 for _, _, b in dets) and all(x > 0 for _, x, _ in dets),
          "shipradar defaults: detections in t_s order, bearings in [0, 360), ranges > 0")
    gaps = [b[0] - a[0] for rows in truth.values() for a, b in zip(rows, rows[1:])]
    firsts, lasts = [rows[0][0] for rows in truth.values()], [rows[-1][0] for rows in truth.values()]
    check(sorted(truth) == list(range(1, 41)) and min(gaps) >= 2 - 1e-6 and max(gaps) <= 10 + 1e-6 and max(firsts) < 10
          and 0 <= min(firsts) and min(lasts) > T - 10 and max(lasts) <= T and max(gaps) - min(gaps) > 7,
          "shipradar defaults: targets 1..40, AIS intervals in [%.3f, %.3f] s (bounds 2, 10), first report by %.2f s, "
          "last after %.2f s" % (min(gaps), max(gaps), max(firsts), min(lasts)))

    def speed(a, b):
        e, n, _ = enu(a[1], a[2], 0.0, ecef(b[1], b[2], 0.0))
        return math.hypot(e, n) / (b[0] - a[0])
    vo = [speed(a, b) for a, b in zip(obs, obs[1:])]
    vt = [speed(a, b) for rows in truth.values() for a, b in zip(rows, rows[1:])]
    check(max(vo) - min(vo) < 0.01 and 2 - 0.01 < vo[0] < 6.01 and max(vt) < 10.01
          and all(h == 15 for _, _, _, h, _ in obs) and [o[0] for o in obs] == list(range(T + 1)),
          "shipradar defaults: own ship at %.2f m/s (bounds 2, 6), 1 s samples, antenna at 15 m; targets up to %.2f m/s"
          % (vo[0], max(vt)))


def main():
    with tempfile.TemporaryDirectory() as tmp:
        check_determinism(tmp)
        check_geodesy()
        check_polar(tmp)
        check_uav_bearings(tmp)
        check_bad_input(tmp)
        check_intercept(tmp)
        check_ship_geometry(tmp)
        check_ship_defaults(tmp)
    print("%d failure(s)" % len(FAILS) if FAILS else "all checks passed")
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
