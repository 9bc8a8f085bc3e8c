#!/usr/bin/env python3
"""Checks of scripts/flightgen.py shipradar's harbour (scene=harbour and its keys), fixed seeds,
each bound derived from the sample or from the printed precision and said why in its line.

a. Geometry, noise-free (sigmas 0, p_detect 1, no clutter, land or merging; own ship straight so
   that observer.csv interpolates exactly): every ship detection = the near side of its hull computed
   here (this file's WGS84, the hull in the tangent plane at the AIS antenna, nearest distance as
   the minimum over the rectangle's four edges, bearing = middle of the corners' angular extent);
   the range shortfall against the antenna within its exact bounds [min(A, L - A, C, D), farthest
   corner]; moored ships' AIS positions constant; cluster neighbours alongside: hull centres
   (B_i + B_j) / 2 + [1, 3] m apart to starboard, none ahead; drawn dimensions within their ranges.
   Placement: dense clusters near a close shore: none within its half diagonal + 10 m of the
   shore, no hull circles of different clusters meeting, some draws mirrored and replaced.
b. Coloured noise: the lag-1 autocorrelation of each ship's bearing and range errors between
   successive illuminations = mean exp(-dt / tau) (bias -2 rho / n of the known-mean estimator
   added) within 3 standard errors sqrt((1 - rho^2) / N) (Bartlett, AR(1)); the variance against
   each ship's own sigma within a chi-square band (99.9 %, effective dof N (1 - rho^2) / (1 + rho^2));
   white noise (noise_tau_s = 0): lag-1 within 3 / sqrt(N) of 0.
c. AIS: stamps whole seconds, intervals in [max(1, round(ais_min_s)), round(ais_max_s)], the
   position at the whole second = the antenna's (dense reference of the same geometry); silent ships
   in neither truth.csv nor targets.csv, their count and the wrong static data's in binomial bands
   (3.3 SD, 99.9 %); targets.csv = the true dimensions to the whole metre, the wrong ones scaled by
   factors in [0.3, 3] with the antenna in the same place of the stated hull.
d. Unresolved: two ships moored side by side, closer than range_resolution_m and within
   beamwidth_deg every scan (checked here): one detection per scan at their mean (weights: hull
   lengths) computed here; with range_resolution_m 0 two detections per scan.
e. Sea clutter: its count Poisson (3.5 SD), per-scan dispersion chi-square, mean range of the
   truncated exponential within 3.5 SE, bearings uniform, stamps at the beam's passage; land:
   each reflector on the shore line, each of its detections = that fixed point's range and bearing
   from observer.csv, the detected share of reflector-scans in range binomial (3.5 SD), none out of range.
f. scene=open: no targets.csv, the same file set; every new key set to its off value gives
   byte-identical files; harbour defaults taken, --set wins over them; bad keys refused by name.

  PYTHONPATH=SOURCE_DIR/scripts check_harbour_gen.py SOURCE_DIR (ctest sets PYTHONPATH)
"""
import math
import os
import subprocess
import sys
import tempfile

import flightgen
from generated_checks import Checks

SRC = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
GEN = os.path.join(SRC, "scripts", "flightgen.py")
checks = Checks("check_harbour_gen")
check = checks.check

A_WGS, F_WGS = 6378137.0, 1 / 298.257223563
B_WGS = A_WGS * (1 - F_WGS)
QUIET = {"bearing_sigma_deg": 0, "bearing_sigma_max_deg": 0, "range_sigma_m": 0, "range_sigma_max_m": 0,
         "p_detect": 1, "sea_clutter_per_scan": 0, "land_points": 0, "range_resolution_m": 0}


# ---- this file's own geodesy and hull geometry
def ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A_WGS * A_WGS / math.sqrt((A_WGS * math.cos(la)) ** 2 + (B_WGS * math.sin(la)) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (B_WGS / A_WGS) ** 2 + h) * math.sin(la))


def axes(lat, lon):
    """East, north, up unit vectors (ECEF) at (lat, lon)."""
    la, lo = math.radians(lat), math.radians(lon)
    return ((-math.sin(lo), math.cos(lo), 0.0),
            (-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)),
            (math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def add(a, b, s=1.0):
    return [x + s * y for x, y in zip(a, b)]


def dang(a, b):
    return abs((a - b + 540.0) % 360.0 - 180.0)


class Radar:
    """The radar antenna at (lat, lon, h): ENU of ECEF points."""

    def __init__(self, lat, lon, h, p=None):
        self.o, self.ax = p or ecef(lat, lon, h), axes(lat, lon)

    def enu(self, p):
        d = sub(p, self.o)
        return [dot(a, d) for a in self.ax]


def bearing(v):
    return math.degrees(math.atan2(v[0], v[1]))


def seg_dist(p, q):
    """Distance from the origin to the segment p-q (3-D)."""
    d = sub(q, p)
    s = min(1.0, max(0.0, -dot(p, d) / dot(d, d)))
    return math.sqrt(dot(add(p, d, s), add(p, d, s)))


def hull_corners(p, lat, lon, heading, t):
    """The hull's corners (ECEF), centre, and (forward, starboard) of target info t with its
    antenna at ECEF p, (lat, lon), true heading [deg]."""
    e, n, _ = axes(lat, lon)
    h = math.radians(heading)
    fwd = add([math.sin(h) * x for x in e], n, math.cos(h))
    stb = add([math.cos(h) * x for x in e], n, -math.sin(h))
    L, B, A, C = t["length_m"], t["beam_m"], t["to_bow_m"], t["to_port_m"]
    pt = lambda x, y: add(add(p, fwd, x), stb, y)
    return [pt(A, -C), pt(A, B - C), pt(A - L, B - C), pt(A - L, -C)], pt(A - L / 2, B / 2 - C), fwd, stb


def near_side(radar, corners, centre):
    """(range, bearing) of the hull's echo: the nearest point of the rectangle (its edges, unless
    the radar is over it) and the middle of the corners' angular extent."""
    q = [radar.enu(c) for c in corners]
    r = min(seg_dist(q[i], q[(i + 1) % 4]) for i in range(4))
    # over the hull: the foot of the perpendicular inside the rectangle
    u, v = sub(q[1], q[0]), sub(q[3], q[0])
    s, w = -dot(q[0], u) / dot(u, u), -dot(q[0], v) / dot(v, v)
    bc = bearing(radar.enu(centre))
    if 0 <= s <= 1 and 0 <= w <= 1:
        foot = add(add(q[0], u, s), v, w)
        return math.sqrt(dot(foot, foot)), bc
    d = [(bearing(x) - bc + 540.0) % 360.0 - 180.0 for x in q]
    return r, (bc + (min(d) + max(d)) / 2) % 360.0


def interp_rows(rows, t, cols):
    """(ECEF at h, [lat, lon, h]) of rows (t, lat, lon[, h], ...) linearly interpolated at t (ECEF
    for the point, the geodetic values for the frame's axes)."""
    lo, hi = 0, len(rows) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if rows[mid][0] <= t else (lo, mid)
    w = (t - rows[lo][0]) / (rows[hi][0] - rows[lo][0]) if rows[hi][0] > rows[lo][0] else 0.0
    g = [rows[lo][c] + w * (rows[hi][c] - rows[lo][c]) for c in cols] + [0.0] * (3 - len(cols))
    a = ecef(*([rows[lo][c] for c in cols] + [0.0] * (3 - len(cols))))
    b = ecef(*([rows[hi][c] for c in cols] + [0.0] * (3 - len(cols))))
    return add(a, sub(b, a), w), g


def by_target(truth):
    out = {}
    for row in truth:
        out.setdefault(row[1], []).append((row[0], row[2], row[3]))
    return out


def ship_dets(res):
    """{id: [(t, range, bearing)]} of the detections of one ship alone (sources)."""
    out = {}
    for d, s in zip(res["detections"], res["sources"]):
        if s[0] == "ship" and len(s[1]) == 1:
            out.setdefault(s[1][0], []).append((d[0], d[2], d[3]))
    return out


def echo_at(res, tracks, info, t):
    """(range, bearing, antenna range) of a ship's echo at t, here: own antenna from observer.csv's
    rows, the ship's antenna from its AIS rows (moored: its first report, heading on record;
    moving: interpolated, heading = its track's direction)."""
    p_o, g_o = interp_rows(res["observer"], t, (1, 2, 3))
    radar = Radar(*g_o, p=p_o)
    rows = tracks[info["id"]]
    if info["moored"]:
        lat, lon = rows[0][1:3]
        p, heading = ecef(lat, lon, 0.0), info["heading_deg"]
    else:
        p, (lat, lon, _) = interp_rows(rows, t, (1, 2))
        j = max(1, min(len(rows) - 1, next((k for k, r in enumerate(rows) if r[0] > t), len(rows) - 1)))
        e, n, _ = axes(lat, lon)
        d = sub(ecef(rows[j][1], rows[j][2], 0.0), ecef(rows[j - 1][1], rows[j - 1][2], 0.0))
        heading = math.degrees(math.atan2(dot(d, e), dot(d, n)))
    corners, centre, _, _ = hull_corners(p, lat, lon, heading, info)
    r, b = near_side(radar, corners, centre)
    q = radar.enu(p)
    return r, b, math.sqrt(dot(q, q))


# ---- a
def check_geometry(tmp):
    keys = dict(QUIET, scene="harbour", duration_s=300, n_targets=30, moored_fraction=0.5, turn_fraction=0,
                obs_turns=0, ais_min_s=0.5, ais_max_s=0.5, ais_whole_seconds=0, ais_silent_fraction=0)
    res = flightgen.shipradar(os.path.join(tmp, "geo"), 21, keys)
    info = {t["id"]: t for t in res["targets"]}
    tracks, dets = by_target(res["truth"]), ship_dets(res)
    worst = {True: [0.0, 0.0, 0], False: [0.0, 0.0, 0]}
    short, bad_short = [], 0
    for i, rows in dets.items():
        t_i = info[i]
        fast = not t_i["moored"] and t_i["speed_mps"] > 1.0
        if not (t_i["moored"] or fast):
            continue
        for t, r, b in rows:
            r2, b2, ra = echo_at(res, tracks, t_i, t)
            w = worst[t_i["moored"]]
            w[0], w[1], w[2] = max(w[0], abs(r - r2)), max(w[1], dang(b, b2) * math.radians(1) * r), w[2] + 1
            L, B, A, C = t_i["length_m"], t_i["beam_m"], t_i["to_bow_m"], t_i["to_port_m"]
            lo, hi = min(A, L - A, C, B - C), max(math.hypot(x, y) for x in (A, L - A) for y in (C, B - C))
            bad_short += not lo - 1e-3 <= ra - r <= hi + 1e-3
            short.append((ra - r) / L)
    # moored: every row of its own (1 s observer rows interpolated: < 1e-6 m off a straight leg of
    # 6 m; the rest is floating point); moving: heading from 0.5 s AIS chords (< 1e-4 m at 300 m)
    check(worst[True][2] > 1000 and worst[True][0] < 1e-5 and worst[True][1] < 1e-5,
          "geometry: %d detections of moored ships = near side computed here: max %.1e m in range, %.1e m across "
          "(bounds 1e-5 m)" % (worst[True][2], worst[True][0], worst[True][1]))
    check(worst[False][2] > 300 and worst[False][0] < 1e-3 and worst[False][1] < 1e-3,
          "geometry: %d detections of moving ships (> 1 m/s, straight) = near side computed here: max %.1e m in "
          "range, %.1e m across (bounds 1e-3 m: heading from 0.5 s AIS chords)" % (worst[False][2], *worst[False][:2]))
    check(bad_short == 0 and len(short) > 1000 and max(short) < 1 and max(short) > 0.3,
          "geometry: range shortfall vs the AIS antenna within [min(A, L - A, C, D), farthest corner] for all %d "
          "(%d outside); shortfall / L in [%.3f, %.3f]" % (len(short), bad_short, min(short), max(short)))
    moored = [t for t in res["targets"] if t["moored"]]
    const = all(len({(la, lo) for _, la, lo in tracks[t["id"]]}) == 1 for t in moored)
    check(len(moored) >= 8 and const, "geometry: the %d moored ships' AIS positions constant" % len(moored))
    check_clusters(res, tracks, info)
    allt = [t for s in (21, 22, 23) for t in flightgen.shipradar(os.path.join(tmp, "geo_d"), s, dict(
        keys, duration_s=60, n_targets=200, land_points=0))["targets"]]
    dims_ok = all(10 - 1e-9 <= t["length_m"] <= 300 + 1e-9 and (abs(t["beam_m"] - 3) < 1e-12 or 0.12 - 1e-12
                  <= t["beam_m"] / t["length_m"] <= 0.2 + 1e-12) and t["beam_m"] >= 3
                  and 0.15 <= t["to_bow_m"] / t["length_m"] <= 0.85 and 0.2 <= t["to_port_m"] / t["beam_m"] <= 0.8
                  for t in allt)
    # log-uniform: ln L uniform on [ln 10, ln 300], mean and SD (b - a) / sqrt(12)
    lg = [math.log(t["length_m"]) for t in allt]
    a, b = math.log(10), math.log(300)
    se = (b - a) / math.sqrt(12 * len(lg))
    m = sum(lg) / len(lg)
    check(dims_ok and abs(m - (a + b) / 2) < 3.5 * se,
          "geometry: %d hulls: L in [10, 300], B = max(3, L [0.12, 0.2]), A / L in [0.15, 0.85], C / B in "
          "[0.2, 0.8]; mean ln L %.3f, log-uniform %.3f +- %.3f (3.5 SE)" % (len(allt), m, (a + b) / 2, 3.5 * se))


def check_clusters(res, tracks, info):
    clusters = {}
    for t in res["targets"]:
        if t["moored"]:
            clusters.setdefault(t["cluster"], []).append(t)
    pairs, bad, gaps, ahead, par = 0, 0, [], 0.0, 0.0
    for members in clusters.values():
        for t1, t2 in zip(members, members[1:]):
            cs = []
            for t in (t1, t2):
                lat, lon = tracks[t["id"]][0][1:3]
                cs.append(hull_corners(ecef(lat, lon, 0.0), lat, lon, t["heading_deg"], t)[1:])
            d = sub(cs[1][0], cs[0][0])
            along, right = dot(d, cs[0][1]), dot(d, cs[0][2])
            gap = right - (t1["beam_m"] + t2["beam_m"]) / 2
            pairs += 1
            gaps.append(gap)
            # parallel: the second forward vector's bearing in the first hull's tangent plane (true
            # headings differ by the change of the meridian convergence across the cluster, 5e-4 deg
            # per 30 m at 63 deg N; the 3-D angle by the tangent planes' tilt, 1e-5 rad per 64 m)
            angle = dang(math.degrees(math.atan2(dot(cs[1][1], cs[0][2]), dot(cs[1][1], cs[0][1]))), 0.0)
            ahead, par = max(ahead, abs(along)), max(par, angle)
            bad += not (1 - 1e-3 <= gap <= 3 + 1e-3)
    # the layout is in the plane, the hulls in the tangent plane at each antenna: they agree to
    # (distance / earth radius)^2 of 50 m, far below 1 mm
    check(pairs >= 4 and bad == 0 and ahead < 1e-3 and par < 1e-5,
          "geometry: %d cluster neighbours alongside: centre gap - (Bi + Bj)/2 in [%.3f, %.3f] m (bounds 1, 3), "
          "max %.1e m ahead, hulls parallel within %.1e deg" % (pairs, min(gaps or [0]), max(gaps or [0]), ahead, par))


def check_placement(tmp):
    """Dense moored clusters near a close shore, all at rest so that AIS gives their places: at t_p
    no hull within its half diagonal + 10 m of the shore, no two hulls' circles of different
    clusters meeting (the rule of the docstring), and some draws mirrored and replaced to get there."""
    keys = dict(scene="harbour", duration_s=60, n_targets=120, moored_fraction=1, target_min_range_m=250,
                target_max_range_m=2500, land_distance_m=1500, obs_speed_mps=0, place_time_frac=0,
                ais_silent_fraction=0, sea_clutter_per_scan=0, land_points=20)
    res = flightgen.shipradar(os.path.join(tmp, "place"), 81, keys)
    P, tracks = res["params"], by_target(res["truth"])
    site = Radar(P["lat_deg"], P["lon_deg"], 0.0)
    lb = math.radians(P["land_bearing_deg"])
    hulls = []
    for t in res["targets"]:
        lat, lon = tracks[t["id"]][0][1:3]
        c = site.enu(hull_corners(ecef(lat, lon, 0.0), lat, lon, t["heading_deg"], t)[1])
        hulls.append((c, math.hypot(t["length_m"], t["beam_m"]) / 2, t["cluster"]))
    # the shore's normal coordinate in the start's ENU is the plane's within 1 mm (2 km away)
    margin = min(1500 - (c[0] * math.sin(lb) + c[1] * math.cos(lb)) - R for c, R, _ in hulls)
    meet = sum(1 for a in range(len(hulls)) for b in range(a) if hulls[a][2] != hulls[b][2]
               and math.hypot(hulls[a][0][0] - hulls[b][0][0], hulls[a][0][1] - hulls[b][0][1]) < hulls[a][1] + hulls[b][1] - 1e-3)
    check(margin > 10 - 1e-3 and meet == 0 and P["n_replaced"] > 0 and P["n_mirrored"] > 0,
          "placement: 120 moored ships in %d clusters within 2.5 km, shore 1.5 km off: nearest hull circle %.1f m short "
          "of the shore (bound 10 m), %d circles of different clusters meeting; %d ships mirrored off the shore, %d "
          "groups redrawn" % (P["n_clusters"], margin, meet, P["n_mirrored"], P["n_replaced"]))


# ---- b
def errors(res):
    """{id: [(dt to the previous illumination or None, range error, bearing error)]} in time order,
    dt None where the previous illumination gave no detection of the ship alone."""
    lit = {}
    for t, i, k, r, b, seen in res["illuminations"]:
        lit.setdefault(i, []).append((t, r, b))
    dets = ship_dets(res)
    out = {}
    for i, rows in lit.items():
        d = {round(t, 9): (r, b) for t, r, b in dets.get(i, [])}
        seq, prev = [], None
        for t, r, b in rows:
            m = d.get(round(t, 9))
            if m is None:
                prev = None
                continue
            seq.append((None if prev is None else t - prev, m[0] - r, (m[1] - b + 540.0) % 360.0 - 180.0))
            prev = t
        out[i] = seq
    return out


def chi2_quantile(nu, z):
    """Wilson-Hilferty: the chi-square quantile at the normal deviate z."""
    return nu * (1 - 2 / (9 * nu) + z * math.sqrt(2 / (9 * nu))) ** 3


def check_noise(tmp):
    base = dict(scene="harbour", duration_s=1800, n_targets=40, moored_fraction=1, p_detect=1, land_points=0,
                sea_clutter_per_scan=0, range_resolution_m=0, target_min_range_m=1000, target_max_range_m=5000)
    for tau in (20.0, 5.0, 0.0):
        res = flightgen.shipradar(os.path.join(tmp, "noise"), 31, dict(base, noise_tau_s=tau))
        sig = {t["id"]: (t["range_sigma_m"], t["bearing_sigma_deg"]) for t in res["targets"]}
        for ch, name in ((1, "range"), (2, "bearing")):
            num = den = sq = phi_sum = 0.0
            n_pairs = n_all = 0
            per_ship = []
            for i, seq in errors(res).items():
                s = sig[i][ch - 1]
                for k, x in enumerate(seq):
                    sq, n_all = sq + (x[ch] / s) ** 2, n_all + 1
                    if x[0] is not None:
                        num += seq[k - 1][ch] * x[ch] / s ** 2
                        den += seq[k - 1][ch] ** 2 / s ** 2
                        phi_sum += math.exp(-x[0] / tau) if tau > 0 else 0.0
                        n_pairs += 1
                per_ship.append(len(seq))
            rho = phi_sum / n_pairs
            n_ser = sum(per_ship) / len(per_ship)
            expect = rho * (1 - 2 / n_ser)
            se = math.sqrt((1 - rho * rho) / n_pairs)
            r1 = num / den
            check(n_pairs > 20000 and abs(r1 - expect) < 3 * se,
                  "noise tau %g s, %s: lag-1 autocorrelation %.4f over %d pairs, expected exp(-dt/tau) %.4f "
                  "(with bias -2 rho/n, n = %.0f: %.4f) +- %.4f (3 SE, sqrt((1 - rho^2)/N))"
                  % (tau, name, r1, n_pairs, rho, n_ser, expect, 3 * se))
            nu = n_all * (1 - rho * rho) / (1 + rho * rho)
            lo, hi = chi2_quantile(nu, -3.29) / nu, chi2_quantile(nu, 3.29) / nu
            check(lo < sq / n_all < hi,
                  "noise tau %g s, %s: mean (error / own sigma)^2 %.4f over %d, chi-square band [%.4f, %.4f] "
                  "(99.9 %%, %.0f effective dof)" % (tau, name, sq / n_all, n_all, lo, hi, nu))
    sb = [t["bearing_sigma_deg"] for t in res["targets"]]
    sr = [t["range_sigma_m"] for t in res["targets"]]
    # 40 uniform draws all in one half of the range: probability 2 * 0.5^40
    check(0.5 <= min(sb) and max(sb) <= 1.5 and max(sb) - min(sb) > 0.5 and 15 <= min(sr) and max(sr) <= 80
          and max(sr) - min(sr) > 32.5,
          "noise: 40 ships' bearing sigmas in [%.3f, %.3f] (bounds 0.5, 1.5), range sigmas in [%.1f, %.1f] (15, 80)"
          % (min(sb), max(sb), min(sr), max(sr)))


# ---- c
def read_csv(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0], [ln.split(",") for ln in lines[1:]]


def band(n, p, z=3.3):
    """Binomial (n, p) count bounds at z SD plus the continuity half unit."""
    sd = math.sqrt(n * p * (1 - p))
    return n * p - z * sd - 0.5, n * p + z * sd + 0.5


def check_ais(tmp):
    keys = dict(scene="harbour", duration_s=120, n_targets=200, land_points=0, sea_clutter_per_scan=0)
    ships, rows_all, stamps_ok, gaps_bad, n_gaps = [], [], True, 0, 0
    absent_ok = True
    for seed in (41, 42, 43):
        d = os.path.join(tmp, "ais%d" % seed)
        res = flightgen.shipradar(d, seed, keys)
        _, truth = read_csv(os.path.join(d, "truth.csv"))
        hdr, tg = read_csv(os.path.join(d, "targets.csv"))
        stamps_ok &= hdr == "target,length_m,beam_m,to_bow_m,to_port_m" and all(r[0].endswith(".000000") for r in truth)
        times = {}
        for r in truth:
            times.setdefault(int(r[1]), []).append(float(r[0]))
        for ts in times.values():
            for a, b in zip(ts, ts[1:]):
                gaps_bad += not 2 <= b - a <= 10
                n_gaps += 1
        silent = {t["id"] for t in res["targets"] if t["silent"]}
        absent_ok &= set(times) == {int(r[0]) for r in tg} == {t["id"] for t in res["targets"]} - silent
        info = {t["id"]: t for t in res["targets"]}
        rows_all += [(info[int(r[0])], [int(x) for x in r[1:]]) for r in tg]
        ships += res["targets"]
    check(stamps_ok and n_gaps > 1000 and gaps_bad == 0,
          "ais: every stamp a whole second, %d intervals in [2, 10] s (%d outside)" % (n_gaps, gaps_bad))
    n_sil = sum(t["silent"] for t in ships)
    lo, hi = band(len(ships), 0.1)
    check(absent_ok and lo <= n_sil <= hi,
          "ais: %d of %d ships silent (binomial band [%.0f, %.0f]), none in truth.csv or targets.csv, every other in both"
          % (n_sil, len(ships), lo, hi))
    n_wrong = sum(t["wrong_dims"] for t, _ in rows_all)
    lo, hi = band(len(rows_all), 0.1)
    right = [(t, r) for t, r in rows_all if not t["wrong_dims"]]
    exact = all(abs(r[0] - t["length_m"]) <= 0.5 and abs(r[1] - t["beam_m"]) <= 0.5 and abs(r[2] - t["to_bow_m"]) <= 0.5
                and abs(r[3] - t["to_port_m"]) <= 0.5 for t, r in right)
    # wrong: stated / true in [0.3, 3] each (whole metres: +-0.5 m), the antenna's share of the hull kept
    wrong_ok = all(0.3 * t["length_m"] - 0.5 <= r[0] <= 3 * t["length_m"] + 0.5
                   and 0.3 * t["beam_m"] - 0.5 <= r[1] <= 3 * t["beam_m"] + 0.5
                   and abs(r[2] - r[0] * t["to_bow_m"] / t["length_m"]) <= 1.0
                   and abs(r[3] - r[1] * t["to_port_m"] / t["beam_m"]) <= 1.0 for t, r in rows_all if t["wrong_dims"])
    off = sum(abs(r[0] - t["length_m"]) > 0.5 for t, r in rows_all if t["wrong_dims"])
    check(lo <= n_wrong <= hi and exact and wrong_ok and off > 0.8 * n_wrong,
          "ais: %d of %d targets.csv rows wrong (binomial band [%.0f, %.0f]), %d of them off in length; the %d others "
          "= the true dimensions to the whole metre" % (n_wrong, len(rows_all), lo, hi, off, len(right)))
    check_ais_positions(tmp)


def check_ais_positions(tmp):
    keys = dict(scene="harbour", duration_s=300, n_targets=30, land_points=0, sea_clutter_per_scan=0,
                ais_silent_fraction=0, ais_min_s=2.6, ais_max_s=5.4)
    a = flightgen.shipradar(os.path.join(tmp, "aisw"), 44, keys)
    b = flightgen.shipradar(os.path.join(tmp, "aisd"), 44, dict(keys, ais_whole_seconds=0, ais_min_s=0.5, ais_max_s=0.5))
    ref, worst, gaps = by_target(b["truth"]), 0.0, set()
    for i, rows in by_target(a["truth"]).items():
        gaps |= {round(q[0] - p[0], 9) for p, q in zip(rows, rows[1:])}
        for t, la, lo in rows:
            p, _ = interp_rows(ref[i], t, (1, 2))
            worst = max(worst, math.dist(p, ecef(la, lo, 0.0)))
    # ais_min_s 2.6, ais_max_s 5.4: rounded half up the intervals are 3, 4 or 5 s; the 0.5 s chords
    # of the same tracks miss a turn at 0.5 deg/s and 10 m/s by v w dt^2 / 8 < 3 mm
    check(worst < 0.01 and gaps == {3.0, 4.0, 5.0},
          "ais: whole-second reports = the antenna at that second (0.5 s reference of the same geometry) within "
          "%.1e m (bound 0.01 m); intervals %s s (ais 2.6-5.4 s rounded: 3, 4, 5)" % (worst, sorted(gaps)))


# ---- d
def check_unresolved(tmp):
    keys = dict(QUIET, scene="harbour", duration_s=300, n_targets=2, moored_fraction=1, cluster_max=2,
                hull_min_length_m=15, hull_max_length_m=25, target_min_range_m=3000, target_max_range_m=3500,
                range_resolution_m=60, beamwidth_deg=1.5, ais_silent_fraction=0, obs_turns=0)
    res = flightgen.shipradar(os.path.join(tmp, "merge"), 51, keys)
    info = {t["id"]: t for t in res["targets"]}
    tracks = by_target(res["truth"])
    lit = {}
    for t, i, k, r, b, seen in res["illuminations"]:
        lit.setdefault(k, {})[i] = t
    per, om, b0 = 2.5, 144.0, 0.0
    dets = {}
    for d, s in zip(res["detections"], res["sources"]):
        dets.setdefault(int(d[0] // per), []).append((d, s))
    premise = worst_t = worst_r = worst_b = beam = 0.0
    bad = 0
    for k, ts in lit.items():
        if len(ts) != 2:
            bad += 1
            continue
        e = {i: echo_at(res, tracks, info[i], t)[:2] for i, t in ts.items()}
        for i, t in ts.items():      # the beam's bearing at the illumination = the echo's (here)
            beam = max(beam, dang(b0 + (t - k * per) * om, e[i][1]))
        premise = max(premise, abs(e[1][0] - e[2][0]) / 60, dang(e[1][1], e[2][1]) / 1.5)
        w = {i: info[i]["length_m"] for i in (1, 2)}
        W = w[1] + w[2]
        mt = (w[1] * ts[1] + w[2] * ts[2]) / W
        mr = (w[1] * e[1][0] + w[2] * e[2][0]) / W
        mb = e[1][1] + w[2] * ((e[2][1] - e[1][1] + 540.0) % 360.0 - 180.0) / W
        got = dets.get(k, [])
        if len(got) != 1 or got[0][1] != ("ship", (1, 2)):
            bad += 1
            continue
        d = got[0][0]
        worst_t, worst_r, worst_b = max(worst_t, abs(d[0] - mt)), max(worst_r, abs(d[2] - mr)), max(worst_b, dang(d[3], mb))
    check(len(lit) >= 119 and info[1]["cluster"] == info[2]["cluster"] == 1 and premise < 1 and beam < 1e-6,
          "unresolved: two ships moored side by side, every scan within %.2f of range_resolution_m 60 m / "
          "beamwidth_deg 1.5 (the larger share); lit when the beam points at the echo (max %.1e deg)" % (premise, beam))
    check(bad == 0 and worst_r < 1e-5 and worst_b < 1e-7 and worst_t < 1e-9,
          "unresolved: one detection per scan over %d scans (%d not) at the length-weighted mean computed here: "
          "max %.1e s, %.1e m, %.1e deg" % (len(lit), bad, worst_t, worst_r, worst_b))
    sep = flightgen.shipradar(os.path.join(tmp, "merge0"), 51, dict(keys, range_resolution_m=0))
    counts = {}
    for d in sep["detections"]:
        counts[int(d[0] // per)] = counts.get(int(d[0] // per), 0) + 1
    check(set(counts.values()) == {2} and sep["params"]["n_unresolved_merges"] == 0
          and res["params"]["n_unresolved_merges"] == len(lit),
          "unresolved: range_resolution_m 0: two detections in each of %d scans, no merge (%d merges with 60 m)"
          % (len(counts), res["params"]["n_unresolved_merges"]))


# ---- e
def check_sea_clutter(tmp):
    keys = dict(scene="harbour", duration_s=900, n_targets=1, land_points=0, sea_clutter_per_scan=20,
                sea_clutter_scale_m=1500, min_range_m=50, max_range_m=12000, bearing_bias_deg=0, range_bias_m=0)
    res = flightgen.shipradar(os.path.join(tmp, "sea"), 61, keys)
    sea = [d for d, s in zip(res["detections"], res["sources"]) if s == ("sea",)]
    K, lam = 360, 20.0
    n = len(sea)
    check(abs(n - K * lam) < 3.5 * math.sqrt(K * lam) and res["params"]["n_sea_clutter"] == n,
          "sea clutter: %d returns in %d scans, Poisson mean %.0f +- %.0f (3.5 SD)" % (n, K, K * lam, 3.5 * math.sqrt(K * lam)))
    per_scan = [0] * K
    stamp_bad = 0
    for t, _, r, b in sea:
        k = int(t // 2.5)
        per_scan[k] += 1
        stamp_bad += abs(t - (k * 2.5 + (b % 360.0) / 144.0)) > 1e-5    # bearing printed to 1e-8 deg
    disp = sum((c - lam) ** 2 for c in per_scan) / lam       # chi-square with K - 1 dof for a Poisson
    lo, hi = chi2_quantile(K - 1, -3.29), chi2_quantile(K - 1, 3.29)
    check(lo < disp < hi and stamp_bad == 0,
          "sea clutter: per-scan dispersion %.0f in the chi-square band [%.0f, %.0f] (99.9 %%, %d dof); stamped "
          "when the beam passes (%d off)" % (disp, lo, hi, K - 1, stamp_bad))
    s, R = 1500.0, 12000.0 - 50.0
    q = math.exp(-R / s)
    m1 = s - R * q / (1 - q)                            # mean of the truncated exponential
    m2 = 2 * s * s - (R * R + 2 * s * R) * q / (1 - q)  # its second moment
    sd = math.sqrt(m2 - m1 * m1)
    mr = sum(r - 50.0 for _, _, r, _ in sea) / n
    rng_ok = all(50 <= r <= 12000 for _, _, r, _ in sea)
    c, sn = sum(math.cos(math.radians(b)) for *_, b in sea) / n, sum(math.sin(math.radians(b)) for *_, b in sea) / n
    se_u = 1 / math.sqrt(2 * n)                         # SD of the mean of cos (or sin) of a uniform angle
    check(rng_ok and abs(mr - m1) < 3.5 * sd / math.sqrt(n) and abs(c) < 3.5 * se_u and abs(sn) < 3.5 * se_u,
          "sea clutter: ranges in [50, 12000] m, mean beyond min_range_m %.1f m, truncated exponential %.1f +- %.1f "
          "(3.5 SE); bearings uniform: mean cos %.4f, sin %.4f (+- %.4f)" % (mr, m1, 3.5 * sd / math.sqrt(n), c, sn, 3.5 * se_u))


def check_land(tmp):
    keys = dict(QUIET, scene="harbour", duration_s=600, n_targets=1, land_points=150, land_p_detect=0.7,
                land_distance_m=3000, land_half_length_m=4000, max_range_m=6000, obs_speed_mps=6, obs_turns=0,
                obs_course_deg=30, scan_start_bearing_deg=30)
    res = flightgen.shipradar(os.path.join(tmp, "land"), 71, keys)
    P = res["params"]
    site = Radar(P["lat_deg"], P["lon_deg"], 0.0)
    lb = math.radians(P["land_bearing_deg"])
    nrm, along = (math.sin(lb), math.cos(lb)), (math.cos(lb), -math.sin(lb))
    pts = [ecef(la, lo, 0.0) for la, lo in res["land"]]
    line = [site.enu(p) for p in pts]
    off_line = max(abs(x[0] * nrm[0] + x[1] * nrm[1] - 3000) for x in line)
    spread = [x[0] * along[0] + x[1] * along[1] for x in line]
    # the shore is a line of the plane, mapped to the ellipsoid along its normals: its points' ENU
    # at the own start is the plane's within h d / R (2 m drop x 5 km / 6378 km = 1.6 mm)
    auto = (30 - math.copysign(90, P["obs_turn_deg"])) % 360      # abeam, away from the first turn
    check(len(pts) == 150 and abs(P["land_bearing_deg"] - auto) < 1e-9 and off_line < 0.01
          and max(abs(a) for a in spread) <= 4000.01 and max(spread) - min(spread) > 7000,
          "land: 150 reflectors on the shore 3000 m off the start (max %.1e m off), along it in [%.0f, %.0f] m, "
          "auto bearing abeam %.1f deg (own course 30, first turn %+.1f)" % (off_line, min(spread), max(spread),
                                                                            P["land_bearing_deg"], P["obs_turn_deg"]))
    worst_r = worst_b = 0.0
    seen = set()
    for d, s in zip(res["detections"], res["sources"]):
        if s[0] != "land":
            continue
        p_o, g_o = interp_rows(res["observer"], d[0], (1, 2, 3))
        q = Radar(*g_o, p=p_o).enu(pts[s[1] - 1])
        worst_r = max(worst_r, abs(d[2] - math.sqrt(dot(q, q))))
        worst_b = max(worst_b, dang(d[3], bearing(q)))
        seen.add((s[1], int(d[0] // 2.5)))
    # quadratic in t through three exact points of each scan: (v P / r)^3 terms, < 1e-4 m and 1e-4 deg
    # beyond 500 m at 6 m/s (the reflectors here are at least 3 km away)
    check(len(seen) > 10000 and worst_r < 1e-3 and worst_b < 1e-5,
          "land: %d detections each = its fixed reflector's range and bearing from observer.csv within %.1e m, "
          "%.1e deg (bounds 1e-3 m, 1e-5 deg)" % (len(seen), worst_r, worst_b))
    n_in = det_in = det_out = 0
    for k in range(240):
        p_o, g_o = interp_rows(res["observer"], (k + 0.5) * 2.5, (1, 2, 3))
        radar = Radar(*g_o, p=p_o)
        for j, p in enumerate(pts):
            q = radar.enu(p)
            r = math.sqrt(dot(q, q))
            if 50 + 30 <= r <= 6000 - 30:       # 15 m of own motion in a scan: 30 m off the limits
                n_in += 1
                det_in += (j + 1, k) in seen
            elif r > 6000 + 30:
                det_out += (j + 1, k) in seen
    lo, hi = band(n_in, 0.7, 3.5)
    check(lo <= det_in <= hi and det_out == 0 and 0 < n_in < 150 * 240,
          "land: %d of %d reflector-scans in range detected (binomial band [%.0f, %.0f] at p 0.7, 3.5 SD); %d detected "
          "well beyond max_range_m" % (det_in, n_in, lo, hi, det_out))


# ---- f
OFF = {"scene": "open", "bearing_sigma_max_deg": 0.5, "range_sigma_max_m": 15, "noise_tau_s": 0, "ais_whole_seconds": 0,
       "ais_silent_fraction": 0, "ais_wrong_dims_fraction": 0, "hull_min_length_m": 37, "hull_max_length_m": 0,
       "moored_fraction": 0, "cluster_max": 1, "range_resolution_m": 0, "beamwidth_deg": 0, "sea_clutter_per_scan": 0,
       "sea_clutter_scale_m": 700, "land_points": 0, "land_distance_m": 800, "land_bearing_deg": 17,
       "land_half_length_m": 100, "land_p_detect": 0.2}


def files_of(d):
    return {f: open(os.path.join(d, f), "rb").read() for f in sorted(os.listdir(d))}


def run_cli(*args):
    return subprocess.run([sys.executable, GEN] + list(args), capture_output=True, text=True)


def check_open(tmp):
    new = set(flightgen.KEYS["shipradar"]) - {"duration_s", "lat_deg", "lon_deg", "antenna_h_m", "obs_speed_mps",
                                               "obs_course_deg", "obs_turns", "obs_turn_deg", "obs_turn_rate_dps",
                                               "n_targets", "target_min_range_m", "target_max_range_m",
                                               "place_time_frac", "target_min_speed_mps", "target_max_speed_mps",
                                               "turn_fraction", "scan_period_s", "scan_start_bearing_deg", "max_range_m",
                                               "min_range_m", "p_detect", "range_sigma_m", "bearing_sigma_deg",
                                               "clutter_per_scan", "stamp", "time_offset_s", "range_bias_m", "range_gain",
                                               "bearing_bias_deg", "ais_min_s", "ais_max_s", "ais_sigma_m",
                                               "ais_time_offset_s"}
    check(new == set(OFF), "open: the off values cover every new key (%d)" % len(new))
    effects = {"duration_s": 300, "clutter_per_scan": 2, "ais_sigma_m": 5, "stamp": "scan", "range_gain": 0.001,
               "bearing_bias_deg": 0.2}
    for seed in (1, 2):
        a, b = os.path.join(tmp, "open_a%d" % seed), os.path.join(tmp, "open_b%d" % seed)
        flightgen.shipradar(a, seed, effects)
        flightgen.shipradar(b, seed, dict(effects, **OFF))
        fa, fb = files_of(a), files_of(b)
        check(set(fa) == {"observer.csv", "observer.units.json", "detections.csv", "detections.units.json",
                          "truth.csv", "truth.units.json"} and fa == fb,
              "open seed %d: no targets.csv; every new key at its off value: byte-identical %s" % (seed, ", ".join(fa)))
    h = flightgen.shipradar(os.path.join(tmp, "h1"), 3, {"scene": "harbour", "duration_s": 60})["params"]
    h2 = flightgen.shipradar(os.path.join(tmp, "h2"), 3, {"scene": "harbour", "duration_s": 60, "land_points": 0,
                                                           "target_max_range_m": 4000})["params"]
    want = {"target_min_range_m": 250, "target_max_range_m": 9000, "n_targets": 40, "min_range_m": 50,
            "max_range_m": 12000, "hull_max_length_m": 300, "moored_fraction": 0.4, "cluster_max": 4,
            "range_resolution_m": 30, "beamwidth_deg": 1.5, "sea_clutter_per_scan": 8, "sea_clutter_scale_m": 1500,
            "land_points": 30, "land_distance_m": 3000, "land_half_length_m": 4000, "land_p_detect": 0.7,
            "bearing_sigma_max_deg": 1.5, "range_sigma_max_m": 80, "noise_tau_s": 20, "ais_whole_seconds": 1,
            "ais_silent_fraction": 0.1, "ais_wrong_dims_fraction": 0.1}
    diff = {k: h[k] for k in want if h[k] != want[k]}
    check(not diff and h["n_land"] > 0 and h2["n_land"] == 0 and h2["land_points"] == 0 and h2["target_max_range_m"] == 4000,
          "harbour: its defaults taken (%s), --set wins (land_points 0: no land; target_max_range_m 4000)"
          % (diff or "all %d" % len(want)))
    d = os.path.join(tmp, "bad")
    for args, words in ((("--set", "scene=harbor"), ("scene", "harbor", "harbour")),
                        (("--set", "scene=harbour", "--set", "bearing_sigma_deg=2"), ("bearing_sigma_deg", "bearing_sigma_max_deg")),
                        (("--set", "hull_max_length_m=300", "--set", "hull_min_length_m=400"), ("hull_min_length_m", "hull_max_length_m")),
                        (("--set", "hull_max_length_m=600"), ("hull_max_length_m", "600")),
                        (("--set", "moored_fraction=1.5"), ("moored_fraction", "1.5")),
                        (("--set", "cluster_max=2.5"), ("cluster_max", "2.5")),
                        (("--set", "land_points=-1"), ("land_points", "-1")),
                        (("--set", "ais_whole_seconds=2"), ("ais_whole_seconds", "2"))):
        r = run_cli("shipradar", d, *args)
        err = r.stderr.strip()
        check(r.returncode == 2 and err.startswith("flightgen.py: error:") and "\n" not in err
              and all(w in err for w in words) and not os.path.exists(d),
              "bad input %s: exit %d, %r" % (" ".join(args), r.returncode, err))


def main():
    with tempfile.TemporaryDirectory(prefix="check_harbour_gen.") as tmp:
        check_open(tmp)
        check_geometry(tmp)
        check_placement(tmp)
        check_unresolved(tmp)
        check_ais(tmp)
        check_sea_clutter(tmp)
        check_land(tmp)
        check_noise(tmp)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
