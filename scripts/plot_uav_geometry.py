"""geometry.png of an azimuth-only (UAV) run, from its track.csv (loggers/uav_track.hpp).

Used by plot_uav.py. Three panels of one realization, north up, east right, equal aspect:
(a) plan view: the UAV's true path, the object's true track (start marked), each estimator's
estimate track, and at TIMES_N marked times (pick_times: they follow the convergence, so most
fall where the estimates have not yet converged) the estimates with their 2-sigma position
ellipses (k = 2 on the Mahalanobis distance: the 86.5 % region of a 2-D Gaussian), a line from
each estimate to the true object position at that time, and the measured bearing ray from the
UAV; (b) the same around the object at the marked times but the last; (c) a zoom on the object
at the last marked time, where the ellipses are too small to see in (a) and (b).
"""

import csv
import math

import numpy as np
from matplotlib.patches import Ellipse, Rectangle
from matplotlib.ticker import MaxNLocator

TRACK_NAME = "track.csv"
BASE_COLS = ("realization", "t_s", "uav_north_m", "uav_east_m", "object_north_m", "object_east_m",
             "object_v_north_mps", "object_v_east_mps", "n_bearings", "bearing_rad")
EST_SUFFIXES = ("_north_m", "_east_m", "_v_north_mps", "_v_east_mps", "_P_nn_m2", "_P_ne_m2", "_P_ee_m2")
TIMES_N = 6
ELLIPSE_K = 2.0  # Mahalanobis radius: P(chi2(2) <= k^2) = 1 - exp(-k^2 / 2)
ELLIPSE_P = 1.0 - math.exp(-ELLIPSE_K ** 2 / 2)
C_UAV = "#7f7f7f"
C_OBJ = "black"
C_RAY = "#ff7f0e"


class TrackError(Exception):
    """A malformed track.csv: the message names the file, line and column."""


def read_track(path):
    """track.csv -> (columns {name: np.array}, estimator names in file order)."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise TrackError("%s: cannot read: %s" % (path, e)) from None
    if not rows:
        raise TrackError("%s: line 1: empty (expected the header line)" % path)
    header = [h.strip() for h in rows[0]]
    missing = [c for c in BASE_COLS if c not in header]
    if missing:
        raise TrackError("%s: line 1: header lacks column(s) %s" % (path, ", ".join(missing)))
    names = []
    for h in header:
        if h.endswith("_P_nn_m2"):
            names.append(h[:-len("_P_nn_m2")])
    for n in names:
        lack = [n + s for s in EST_SUFFIXES if n + s not in header]
        if lack:
            raise TrackError("%s: line 1: estimator '%s' lacks column(s) %s" % (path, n, ", ".join(lack)))
    data = []
    for lineno, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(header):
            raise TrackError("%s: line %d: %d fields, the header has %d" % (path, lineno, len(row), len(header)))
        vals = []
        for colno, (name, cell) in enumerate(zip(header, row), start=1):
            try:
                v = float(cell)
            except ValueError:
                raise TrackError("%s: line %d, column %d (%s): '%s' is not a number"
                                 % (path, lineno, colno, name, cell)) from None
            if math.isinf(v) or (math.isnan(v) and not (name == "bearing_rad" or
                                                         any(name.startswith(n + "_") for n in names))):
                raise TrackError("%s: line %d, column %d (%s): '%s' must be finite"
                                 % (path, lineno, colno, name, cell))
            vals.append(v)
        data.append(vals)
    if len(data) < 2:
        raise TrackError("%s: fewer than two frames" % path)
    arr = np.array(data, dtype=float)
    c = {name: arr[:, i] for i, name in enumerate(header)}
    bad = np.nonzero(np.diff(c["t_s"]) <= 0)[0]
    if bad.size:
        raise TrackError("%s: line %d, column %d (t_s): time does not increase"
                         % (path, bad[0] + 3, header.index("t_s") + 1))
    return c, names


def pick_times(c, names, n=TIMES_N):
    """Row indices of up to n frames where every estimator has an estimate: the first frame at
    least 1 s after the first estimate, the last frame, and between them the first frames at
    which the largest 2-sigma semi-major axis (over the estimators) falls below levels spaced
    logarithmically between its values at those two frames - so the times follow the
    convergence, most of them where the estimates are not yet converged. Marked times lie at
    least 1/(4 n) of the span apart."""
    have = np.ones(len(c["t_s"]), dtype=bool)
    for e in names:
        have &= np.isfinite(c[e + "_north_m"]) & np.isfinite(c[e + "_P_nn_m2"])
    idx = np.nonzero(have)[0]
    if idx.size == 0:
        return []
    t = c["t_s"]
    late = idx[t[idx] >= t[idx[0]] + min(1.0, (t[idx[-1]] - t[idx[0]]) / 4)]
    first, last = int(late[0]), int(idx[-1])
    a = np.array([max(semi_major(c, e, i) for e in names) for i in idx])
    a0, a1 = max(semi_major(c, e, first) for e in names), max(semi_major(c, e, last) for e in names)
    gap = (t[last] - t[first]) / (4 * n)  # least spacing of the marked times
    out = [first]
    if a0 > a1 > 0:
        for level in np.geomspace(a0, a1, n)[1:-1]:
            below = np.nonzero((a <= level) & (t[idx] >= t[out[-1]] + gap))[0]
            if below.size and t[idx[below[0]]] <= t[last] - gap:
                out.append(int(idx[below[0]]))
    if last not in out:
        out.append(last)
    return out


def cov_ellipse(x_e, y_n, P_nn, P_ne, P_ee, k, **kw):
    """The ellipse {p: (p - m)^T P^-1 (p - m) <= k^2} in plot axes (x east, y north)."""
    S = np.array([[P_ee, P_ne], [P_ne, P_nn]])  # (east, north) order
    w, v = np.linalg.eigh(S)
    w = np.clip(w, 0.0, None)
    ang = math.degrees(math.atan2(v[1, 1], v[0, 1]))  # direction of the major axis from east, ccw
    return Ellipse((x_e, y_n), 2 * k * math.sqrt(w[1]), 2 * k * math.sqrt(w[0]), angle=ang, **kw)


def semi_major(c, e, i, k=ELLIPSE_K):
    a, b, d = c[e + "_P_nn_m2"][i], c[e + "_P_ne_m2"][i], c[e + "_P_ee_m2"][i]
    return k * math.sqrt(max(0.0, (a + d) / 2 + math.hypot((a - d) / 2, b)))


def fmt_t(t):
    return "%.0f s" % t if t >= 9.95 else "%.1f s" % t


def draw_estimates(ax, c, names, styles, i, lw=1.3):
    """At row i: each estimate with its ellipse and a line to the true object position."""
    on, oe = c["object_north_m"][i], c["object_east_m"][i]
    for e in names:
        lab, col = styles[e]
        n, ea = c[e + "_north_m"][i], c[e + "_east_m"][i]
        ax.add_patch(cov_ellipse(ea, n, c[e + "_P_nn_m2"][i], c[e + "_P_ne_m2"][i], c[e + "_P_ee_m2"][i],
                                 ELLIPSE_K, fill=False, ec=col, lw=lw, zorder=4))
        ax.plot([ea, oe], [n, on], color=col, lw=0.9, ls=(0, (2, 1.5)), zorder=4)
        ax.plot([ea], [n], "o", color=col, ms=4.5, zorder=5)
    ax.plot([oe], [on], "o", color=C_OBJ, ms=4, zorder=6)


def label_uav_times(ax, c, sel):
    """Label the UAV's marked positions with their times, beside its path on the side away from
    the object (across the UAV's velocity); positions closer than 6 % of the path's extent share
    one label."""
    un, ue, t = c["uav_north_m"], c["uav_east_m"], c["t_s"]
    on, oe = c["object_north_m"], c["object_east_m"]
    ext = max(un.max() - un.min(), ue.max() - ue.min(), 1.0)
    groups = []
    for i in sel:
        for g in groups:
            if math.hypot(un[i] - un[g[0]], ue[i] - ue[g[0]]) < 0.06 * ext:
                g.append(i)
                break
        else:
            groups.append([i])
    for g in groups:
        i = g[0]
        j0, j1 = max(i - 1, 0), min(i + 1, len(t) - 1)
        vn, ve = un[j1] - un[j0], ue[j1] - ue[j0]
        dn, de = -ve, vn  # across the path
        if dn * (un[i] - on[i]) + de * (ue[i] - oe[i]) < 0:
            dn, de = -dn, -de
        r = math.hypot(dn, de)
        if r == 0:
            dn, de, r = un[i] - on[i], ue[i] - oe[i], max(math.hypot(un[i] - on[i], ue[i] - oe[i]), 1e-9)
        ax.annotate(", ".join(fmt_t(t[j]) for j in g), (ue[i], un[i]), textcoords="offset points",
                    xytext=(16 * de / r, 16 * dn / r), ha="left" if de > 0.3 * r else "right" if de < -0.3 * r else "center",
                    va="bottom" if dn > 0.3 * r else "top" if dn < -0.3 * r else "center", fontsize=10.5,
                    color="#303030", zorder=7)


def square_limits(ax, e_lo, e_hi, n_lo, n_hi, margin):
    """Equal-aspect square limits around a box, with `margin` (share of its larger side)."""
    half = 0.5 * max(e_hi - e_lo, n_hi - n_lo) * (1 + 2 * margin)
    ce, cn = 0.5 * (e_lo + e_hi), 0.5 * (n_lo + n_hi)
    ax.set_xlim(ce - half, ce + half)
    ax.set_ylim(cn - half, cn + half)
    ax.set_aspect("equal", adjustable="box")
    return ce - half, ce + half, cn - half, cn + half


def style_axes(ax, title):
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.grid(alpha=0.25)
    ax.ticklabel_format(useOffset=False)
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.yaxis.set_major_locator(MaxNLocator(5))
    ax.set_title(title, fontsize=11.5)


def mark_box(ax, lims, label):
    e0, e1, n0, n1 = lims
    ax.add_patch(Rectangle((e0, n0), e1 - e0, n1 - n0, fill=False, ec="0.25", lw=0.9, ls="--", zorder=7))
    ax.annotate(label, (e1, n1), textcoords="offset points", xytext=(2, 2), fontsize=10, color="0.25",
                zorder=7)


def fig_geometry(c, names, styles, summ, path):
    import matplotlib.pyplot as plt

    with plt.rc_context({"font.size": 11}):
        draw_geometry(plt, c, names, styles, summ, path)


def draw_geometry(plt, c, names, styles, summ, path):
    t = c["t_s"]
    real = int(c["realization"][0])
    sel = pick_times(c, names)
    un, ue = c["uav_north_m"], c["uav_east_m"]
    on, oe = c["object_north_m"], c["object_east_m"]
    fig = plt.figure(figsize=(13, 9.2))
    gs = fig.add_gridspec(2, 2, width_ratios=[1.35, 1])
    ax, ao, az = fig.add_subplot(gs[:, 0]), fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])

    # ---- (a) plan view of the whole run
    ax.plot(ue, un, color=C_UAV, lw=1.6, label="UAV path (true)", zorder=2)
    ax.plot([ue[0]], [un[0]], ">", color=C_UAV, ms=8, zorder=3)
    for a in (ax, ao):
        a.plot(oe, on, color=C_OBJ, lw=2.0, zorder=3, label="object, true track" if a is ax else None)
        a.plot([oe[0]], [on[0]], "s", color=C_OBJ, ms=7, mfc="white", mew=1.6, zorder=6,
               label="object's start (t = %s)" % fmt_t(t[0]) if a is ax else None)
    for e in names:  # not in (b): the early tracks' zigzag would hide the ellipses there
        lab, col = styles[e]
        ok = np.isfinite(c[e + "_north_m"])
        ax.plot(c[e + "_east_m"][ok], c[e + "_north_m"][ok], color=col, lw=0.7, alpha=0.6, zorder=2,
                label="%s: estimate track" % lab)
    for a in (ax, ao):
        ray_drawn = False
        for i in sel:
            b, rng = c["bearing_rad"][i], math.hypot(on[i] - un[i], oe[i] - ue[i])
            if math.isfinite(b):
                L = 1.35 * rng
                a.plot([ue[i], ue[i] + L * math.sin(b)], [un[i], un[i] + L * math.cos(b)], color=C_RAY, lw=1.0,
                       zorder=1, label=None if ray_drawn or a is not ax else "measured bearing from the UAV")
                ray_drawn = True
            draw_estimates(a, c, names, styles, i, lw=1.0 if a is ax else 1.4)
    for i in sel:
        ax.plot([ue[i]], [un[i]], "^", color=C_UAV, ms=7, zorder=5)
    label_uav_times(ax, c, sel)
    # Limits: the UAV path and the object's track (early estimates may lie far off).
    lims_a = square_limits(ax, min(ue.min(), oe.min()), max(ue.max(), oe.max()),
                           min(un.min(), on.min()), max(un.max(), on.max()), 0.06)
    seed = summ.get("seed")
    style_axes(ax, "(a) plan view, realization %d%s; marked: t = %s"
               % (real, "" if seed is None else " (seed %d)" % seed, ", ".join(fmt_t(t[i]) for i in sel)))

    # ---- (b) the object's surroundings: the estimates at the marked times
    if sel:
        # the object's positions at the marked times but the last (which (c) shows), the
        # estimates at those but the first (which can lie hundreds of metres off)
        early = sel[:-1] if len(sel) > 2 else sel
        pe = [oe[i] for i in early] + [c[e + "_east_m"][i] for e in names for i in early[1:]]
        pn = [on[i] for i in early] + [c[e + "_north_m"][i] for e in names for i in early[1:]]
        lims_b = square_limits(ao, max(min(pe), lims_a[0]), min(max(pe), lims_a[1]),
                               max(min(pn), lims_a[2]), min(max(pn), lims_a[3]), 0.12)
        vn, ve = c["object_v_north_mps"], c["object_v_east_mps"]
        for i in sel:  # the time beside the true position, across the object's course
            v = math.hypot(vn[i], ve[i]) or 1.0
            ao.annotate(fmt_t(t[i]), (oe[i], on[i]), textcoords="offset points",
                        xytext=(9 * vn[i] / v, -9 * ve[i] / v), ha="left" if vn[i] >= 0 else "right",
                        va="top" if ve[i] >= 0 else "bottom", fontsize=10.5, color=C_OBJ, zorder=8,
                        bbox=dict(fc="white", ec="none", alpha=0.7, pad=0.3))
        style_axes(ao, "(b) around the object, t = %s ... %s" % (fmt_t(t[early[0]]), fmt_t(t[early[-1]])))
        mark_box(ax, lims_b, "(b)")
    else:
        ao.set_axis_off()

    # ---- (c) zoom on the last marked time, where the ellipses are too small for (a) and (b)
    if sel:
        i = sel[-1]
        draw_estimates(az, c, names, styles, i, lw=1.6)
        half = 1.0
        for e in names:
            half = max(half, 1.3 * (semi_major(c, e, i) + math.hypot(c[e + "_north_m"][i] - on[i],
                                                                      c[e + "_east_m"][i] - oe[i])))
        w = np.abs(t - t[i]) * math.hypot(c["object_v_north_mps"][i], c["object_v_east_mps"][i]) <= 2 * half
        az.plot(oe[w], on[w], color=C_OBJ, lw=2.0, zorder=3)
        for e in names:
            lab, col = styles[e]
            ok = w & np.isfinite(c[e + "_north_m"])
            az.plot(c[e + "_east_m"][ok], c[e + "_north_m"][ok], color=col, lw=0.8, alpha=0.75, zorder=2)
        lims_c = square_limits(az, oe[i] - half, oe[i] + half, on[i] - half, on[i] + half, 0.0)
        style_axes(az, "(c) zoom on the object at t = %s" % fmt_t(t[i]))
        lines = ["error, 2σ semi-major axis:"] + [
            "%s: %.2f m, %.2f m" % (e, math.hypot(c[e + "_north_m"][i] - on[i], c[e + "_east_m"][i] - oe[i]),
                                    semi_major(c, e, i)) for e in names]
        az.text(0.03, 0.97, "\n".join(lines), transform=az.transAxes, fontsize=10, va="top",
                bbox=dict(fc="white", ec="0.7", alpha=0.9))
        mark_box(ao, lims_c, "(c)")
    else:
        az.set_axis_off()

    # ---- one legend for all panels
    from matplotlib.lines import Line2D
    h, l = ax.get_legend_handles_labels()
    h += [Line2D([], [], color="0.3", marker="o", ms=4.5, lw=0, mfc="0.3"),
          Line2D([], [], color="0.3", lw=1.3, marker=None),
          Line2D([], [], color="0.3", lw=0.9, ls=(0, (2, 1.5))),
          Line2D([], [], color=C_OBJ, marker="o", ms=4, lw=0),
          Line2D([], [], color=C_UAV, marker="^", ms=7, lw=0)]
    l += ["estimate at a marked time (colour: estimator)",
          "its 2σ position ellipse (k = %g: the %.1f %% region in 2-D)" % (ELLIPSE_K, 100 * ELLIPSE_P),
          "line from the estimate to the true position",
          "object's true position at a marked time",
          "UAV at a marked time"]
    fig.tight_layout(rect=(0, 0.135, 1, 1))
    fig.legend(h, l, loc="lower center", ncol=3, fontsize=10.5, framealpha=0.95)
    fig.savefig(path, dpi=100)
    plt.close(fig)
