#!/usr/bin/python3
"""Figures for the landing-radar (PRL) systematic-error ensemble written by rnav_inproc / rnav_logger.

Usage:  /usr/bin/python3 scripts/plot_prl.py DIR [--switch-time S] [--smooth S]

Reads DIR/stats_time.csv, DIR/stats_range.csv, DIR/table2_detail.json (columns: see
loggers/prl_stats.cpp) and DIR/scenario.json (if present: the switch time, radar site and
Table 2 ranges) and writes into DIR:

  fig1_x.png, fig2_z.png, fig3_y.png  the paper's Figures 1-3 (estimation and compensation of
        the radar's systematic error from SNS data, coordinate X / Z / Y): ensemble-mean error of
        the raw plots (APOI) and of the compensated plots (TOI) against flight time, slant range
        on the top axis, the switch from estimation to compensation, the Table 2 points (ours
        with 95 % bands, the paper's values); lower panel: RMS error.
  fig4_bias.png   error of the bias estimate (estimate - true radar systematic error) per channel:
        ensemble mean and Monte-Carlo RMS against the filter's reported sigma.
  readme_figure.png  compact overview: APOI vs TOI mean error against slant range, X / Z / Y.
  geometry.png    the approach in the landing frame: plan view seen from above (aircraft path,
        radar site, slant-range rings around it, Table 2 ranges, the estimation/compensation
        switch) and the vertical profile; needs DIR/scenario.json and stats_time.csv's
        aircraft_x_m, aircraft_y_m, aircraft_z_m (true position in L).

Needs Debian's python3 with python3-numpy and python3-matplotlib (Agg backend, no display).
Exit code 2 with a message naming the file (and line) when an input is missing or malformed.
"""

import argparse
import csv
import json
import math
import os
import sys

from rnav import figures

PROG = "plot_prl.py"
# matplotlib and numpy, imported by load_plotting() once the arguments are parsed: --help needs
# neither (their import was nine tenths of its half second)
plt = np = matplotlib = None


def load_plotting():
    global plt, np, matplotlib
    plt = figures.pyplot(PROG)  # checks them and sets Agg
    import matplotlib.patches  # noqa: F401
    import matplotlib.ticker  # noqa: F401
    import numpy as np

COORDS = ("x", "z", "y")
COORD_NAME = {"x": "X (along the runway axis)", "z": "Z (lateral)", "y": "Y (vertical)"}
CHANNELS = (("range", "m", "range D"), ("course", "deg", "course angle Ek"),
            ("glide", "deg", "glide angle Eg"))
Z95 = 1.959963984540054

C_APOI = "#d62728"   # raw plots
C_TOI = "#1f77b4"    # compensated plots
C_PAPER = "black"

InputError = figures.InputError


# ----------------------------------------------------------------------------- input


def read_csv(path, required):
    """Read a numeric CSV with a header line; return {column: np.array}.

    Every column in `required` must be present; every data row must have as many fields as
    the header and every field must parse as a finite number.
    """
    if not os.path.isfile(path):
        raise InputError("%s: file not found" % path)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise InputError("%s: line 1: empty file (expected a header line)" % path)
    header = [h.strip() for h in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise InputError("%s: line 1: header lacks column(s) %s" % (path, ", ".join(missing)))
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise InputError("%s: line 1: duplicate column(s) %s" % (path, ", ".join(dup)))
    data = []
    for lineno, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue  # blank line (e.g. trailing newline)
        if len(row) != len(header):
            raise InputError("%s: line %d: %d fields, the header has %d"
                             % (path, lineno, len(row), len(header)))
        vals = []
        for name, cell in zip(header, row):
            try:
                v = float(cell)
            except ValueError:
                raise InputError("%s: line %d: column %s: '%s' is not a number"
                                 % (path, lineno, name, cell)) from None
            if not math.isfinite(v):
                raise InputError("%s: line %d: column %s: '%s' is not finite"
                                 % (path, lineno, name, cell))
            vals.append(v)
        data.append(vals)
    if not data:
        raise InputError("%s: no data rows after the header" % path)
    arr = np.array(data)
    return {name: arr[:, i] for i, name in enumerate(header)}


def load_json(path):
    """The JSON document in path; InputError naming the file, line and column if malformed."""
    try:
        with open(path) as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        raise InputError("%s: line %d column %d: invalid JSON: %s"
                         % (path, e.lineno, e.colno, e.msg)) from None


def read_table2(path):
    """Read table2_detail.json -> {row: [(range_m, mean[3], stderr[3], paper[3] or None)]}."""
    if not os.path.isfile(path):
        raise InputError("%s: file not found" % path)
    doc = load_json(path)
    out = {}
    for row in ("APOI", "TOI"):
        if not isinstance(doc, dict) or not isinstance(doc.get(row), dict):
            raise InputError("%s: missing object '%s'" % (path, row))
        entries = []
        for key, d in doc[row].items():
            where = "%s: %s.%s" % (path, row, key)
            try:
                r = float(key)
            except ValueError:
                raise InputError("%s: range key is not a number" % where) from None
            vals = {}
            for k in ("mean", "stderr") + (("paper",) if "paper" in d else ()):
                v = d.get(k) if isinstance(d, dict) else None
                if (not isinstance(v, list) or len(v) != 3
                        or not all(isinstance(x, (int, float)) for x in v)):
                    raise InputError("%s.%s: expected a list of 3 numbers" % (where, k))
                vals[k] = np.array(v, dtype=float)
            entries.append((r, vals["mean"], vals["stderr"], vals.get("paper")))
        out[row] = sorted(entries, key=lambda e: -e[0])
    if doc.get("range_origin") == "threshold":
        TABLE_SYMBOL[0] = "R_thr"
    out["realizations"] = doc.get("realizations")
    out["seed"] = doc.get("seed")
    return out


TIME_COLS = (["t_s", "range_m", "n"]
             + ["%s_%s_%s_m" % (p, s, c) for p in ("apoi", "toi") for s in ("mean", "rms")
                for c in COORDS]
             + ["biaserr_%s_%s_%s" % (s, ch, u) for s in ("mean", "rms") for ch, u, _ in CHANNELS]
             + ["filter_sd_%s_%s" % (ch, u) for ch, u, _ in CHANNELS])
RANGE_COLS = (["range_lo_m", "range_hi_m", "n"]
              + ["%s_%s_%s_m" % (p, s, c) for p in ("apoi", "toi") for s in ("mean", "rms")
                 for c in COORDS])


# ----------------------------------------------------------------------------- helpers


def running_mean(y, w):
    """Centred running mean over w samples (w odd; shrinking window at the ends)."""
    if w <= 1 or len(y) < 3:
        return y.copy()
    h = w // 2
    c = np.concatenate([[0.0], np.cumsum(y)])
    i = np.arange(len(y))
    lo = np.maximum(i - h, 0)
    hi = np.minimum(i + h + 1, len(y))
    return (c[hi] - c[lo]) / (hi - lo)


def time_at_range(t, rng, r):
    """First time at which the slant range drops to r (linear interpolation), or None."""
    below = np.nonzero(rng <= r)[0]
    if len(below) == 0 or below[0] == 0:
        return None if len(below) == 0 else float(t[0])
    i = below[0]
    f = (rng[i - 1] - r) / (rng[i - 1] - rng[i])
    return float(t[i - 1] + f * (t[i] - t[i - 1]))


TABLE_SYMBOL = ["D"]  # "D" (slant range from the radar) or "R_thr" (range from the threshold)


def table_time(ts, r):
    """Time at which the aircraft is at Table 2 range r, in the sense of table2's range_origin."""
    col = ts["range_table_m"] if "range_table_m" in ts else ts["range_m"]
    return time_at_range(ts["t_s"], col, r)


def range_at_time(t, rng, ts):
    return float(np.interp(ts, t, rng))


def add_range_axis(ax, t, rng):
    """Top x-axis with the slant range (km) at the times the aircraft reaches it."""
    top = ax.twiny()
    top.set_xlim(ax.get_xlim())
    span = (rng.max() - rng.min()) / 1000.0
    step = 2 if span < 20 else 5
    ticks, labels = [], []
    for km in np.arange(0, math.ceil(rng.max() / 1000.0) + step, step):
        tt = time_at_range(t, rng, km * 1000.0)
        if tt is not None and t[0] < tt <= t[-1] and rng.min() <= km * 1000 <= rng.max():
            ticks.append(tt)
            labels.append("%g" % km)
    top.set_xticks(ticks)
    top.set_xticklabels(labels)
    top.set_xlabel("slant range from the radar [km]")
    return top


def ensemble_sd(mean, rms):
    return np.sqrt(np.maximum(rms ** 2 - mean ** 2, 0.0))


def infer_switch_time(ts):
    """First time at which TOI differs from APOI (compensation starts), or None."""
    diff = np.zeros(len(ts["t_s"]), dtype=bool)
    for c in COORDS:
        diff |= np.abs(ts["toi_mean_%s_m" % c] - ts["apoi_mean_%s_m" % c]) > 1e-9
    idx = np.nonzero(diff)[0]
    return float(ts["t_s"][idx[0]]) if len(idx) else None


# ----------------------------------------------------------------------------- figures


def fig_coordinate(fignum, k, c, ts, t2, switch_t, smooth_s, path, toi_is_apoi_before=True):
    """Figure `fignum` for coordinate c (index k into X, Z, Y)."""
    t, rng = ts["t_s"], ts["range_m"]
    n = ts["n"]
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    w = max(1, int(round(smooth_s / dt)) | 1)

    fig, (ax, axr) = plt.subplots(2, 1, figsize=(10, 7.6), sharex=True,
                                  gridspec_kw={"height_ratios": [2.2, 1]})
    # TOI first and wider: before the switch it equals APOI and shows as a blue rim.
    toi_lab = ("TOI (compensated; = APOI before the switch)" if toi_is_apoi_before
               else "TOI (compensated)")
    for pre, col, lab, lw in (("toi", C_TOI, toi_lab, 3.2),
                              ("apoi", C_APOI, "APOI (raw plots)", 1.6)):
        m = ts["%s_mean_%s_m" % (pre, c)]
        rms = ts["%s_rms_%s_m" % (pre, c)]
        half = Z95 * ensemble_sd(m, rms) / np.sqrt(np.maximum(n, 1))
        ax.fill_between(t, m - half, m + half, color=col, alpha=0.12, lw=0)
        ax.plot(t, m, color=col, lw=0.6, alpha=0.4)
        # smooth the estimation and compensation phases separately (no smearing of the step)
        sm = np.empty_like(m)
        for seg in (t < switch_t, t >= switch_t):
            sm[seg] = running_mean(m[seg], w)
        ax.plot(t, sm, color=col, lw=lw, alpha=0.9 if pre == "toi" else 1.0,
                label="%s: ensemble mean, %g s running mean" % (lab, w * dt))
        axr.plot(t, rms, color=col, lw=lw * 0.7, label=lab)
    ax.axhline(0, color="0.4", lw=0.8)

    # Table 2 points: ours (ensemble mean of per-realization bin means, 95 % band) and paper.
    for row, col, mk in (("APOI", C_APOI, "o"), ("TOI", C_TOI, "s")):
        for r, mean, se, paper in t2[row]:
            tt = table_time(ts, r)
            if tt is None:
                continue
            ax.errorbar([tt], [mean[k]], yerr=[Z95 * se[k]], fmt=mk, color=col, mfc="white",
                        ms=7, capsize=4, lw=1.5, zorder=5,
                        label="%s Table 2 point, this run (95 %% band)" % row if r == t2[row][0][0]
                        else None)
            if paper is not None:
                ax.plot([tt], [paper[k]], marker="*" if row == "APOI" else "P", color=C_PAPER,
                        ms=11, ls="none", zorder=6,
                        label="paper Table 2, %s" % row if r == t2[row][0][0] else None)
                ax.annotate("%s %.2f\n(paper %.2f)" % (row, mean[k], paper[k]),
                            (tt, max(mean[k], paper[k]) if row == "APOI" else min(mean[k], paper[k])),
                            textcoords="offset points",
                            xytext=(8, 10) if row == "APOI" else (8, -26), fontsize=8, color=col)
    # y-limits with room for the annotations
    lo, hi = ax.get_ylim()
    span = hi - lo
    ax.set_ylim(lo - 0.12 * span, hi + 0.08 * span)
    lo, hi = ax.get_ylim()
    for r, *_ in t2["APOI"]:
        tt = table_time(ts, r)
        if tt is None:
            continue
        for a in (ax, axr):
            a.axvline(tt, color="0.6", lw=0.8, ls=":")
        # put the label where the curves leave more room at that time
        i = int(np.argmin(np.abs(t - tt)))
        vals = [ts["%s_mean_%s_m" % (p, c)][i] for p in ("apoi", "toi")] + [0.0]
        f_lo, f_hi = (min(vals) - lo) / (hi - lo), (max(vals) - lo) / (hi - lo)
        top = (1 - f_hi) > f_lo
        ax.text(tt, 0.97 if top else 0.03, "%s = %g km " % (TABLE_SYMBOL[0], r / 1000),
                transform=ax.get_xaxis_transform(), fontsize=8, color="0.35", rotation=90,
                va="top" if top else "bottom", ha="right")

    for a in (ax, axr):
        a.axvline(switch_t, color="green", lw=1.3, ls="--")
        a.axvspan(switch_t, t[-1], color="green", alpha=0.05, lw=0)
    ax.text(switch_t, 0.04, "estimation | compensation\nswitch at %g s (D = %.1f km) "
            % (switch_t, range_at_time(t, rng, switch_t) / 1000), transform=ax.get_xaxis_transform(),
            fontsize=8.5, color="green", va="bottom", ha="right",
            bbox=dict(fc="white", ec="green", lw=0.6, alpha=0.9))

    ax.set_xlim(t[0], t[-1])
    ax.set_ylabel("systematic error (ensemble mean) in %s [m]" % c.upper())
    ax.set_title("Fig. %d: estimation and compensation of the radar's systematic error from SNS "
                 "data,\ncoordinate %s; %s realizations, seed %s"
                 % (fignum, COORD_NAME[c], t2.get("realizations"), t2.get("seed")), fontsize=11)
    ax.grid(alpha=0.3)
    add_range_axis(ax, t, rng)

    axr.set_yscale("log")
    axr.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    r_lo, r_hi = axr.get_ylim()
    axr.yaxis.set_major_locator(matplotlib.ticker.LogLocator(
        subs=(1.0, 2.0, 3.0, 5.0) if r_hi / r_lo < 30 else (1.0, 2.0, 5.0)))
    axr.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    axr.set_ylabel("RMS error in %s [m]" % c.upper())
    axr.set_xlabel("flight time [s]")
    axr.grid(alpha=0.3, which="both")
    axr.set_title("RMS error (systematic + fluctuation) of single plots over the ensemble",
                  fontsize=9)
    h, l = ax.get_legend_handles_labels()
    h += [matplotlib.patches.Patch(color="0.5", alpha=0.25)]
    l += ["95 % band of the ensemble mean (per second)"]
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.legend(h, l, loc="lower center", ncol=2, fontsize=8, framealpha=0.95)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig_bias(ts, t2, switch_t, path):
    t, n = ts["t_s"], ts["n"]
    fig, axes = plt.subplots(3, 2, figsize=(12, 9), sharex=True)
    t_lo = min(t[0] + 20.0, switch_t)
    window = (t >= max(t_lo, 100.0 if switch_t > 150 else t_lo)) & (t < switch_t)
    if not window.any():
        window = t < switch_t
    for i, (ch, unit, name) in enumerate(CHANNELS):
        m = ts["biaserr_mean_%s_%s" % (ch, unit)]
        rms = ts["biaserr_rms_%s_%s" % (ch, unit)]
        fsd = ts["filter_sd_%s_%s" % (ch, unit)]
        sd = ensemble_sd(m, rms)
        half = Z95 * sd / np.sqrt(np.maximum(n, 1))
        a = axes[i, 0]
        a.fill_between(t, m - half, m + half, color="C0", alpha=0.2, lw=0,
                       label="95 % band of the mean")
        a.plot(t, m, color="C0", lw=1.2, label="ensemble mean of (estimate - true)")
        a.plot(t, fsd, color="C1", lw=1, ls="--", label="+- filter sigma")
        a.plot(t, -fsd, color="C1", lw=1, ls="--")
        a.axhline(0, color="0.4", lw=0.8)
        # y-limits from the settled part (the first seconds are the +-bias start-up transient)
        settled = t >= t_lo
        lim = 1.3 * max(np.max(np.abs(m[settled]) + half[settled]), np.max(fsd[settled]))
        a.set_ylim(-lim, lim)
        a.set_ylabel("%s error [%s]" % (name, unit))
        a.grid(alpha=0.3)

        b = axes[i, 1]
        b.plot(t, rms, color="C3", lw=1.4, label="Monte-Carlo RMS of (estimate - true)")
        b.plot(t, sd, color="C2", lw=1, ls=":", label="Monte-Carlo SD")
        b.plot(t, fsd, color="C1", lw=1.4, ls="--", label="filter sigma sqrt(mean p)")
        b.set_yscale("log")
        b.yaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        b.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        b.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        b.set_ylabel("%s error [%s]" % (name, unit))
        b.grid(alpha=0.3, which="both")
        ok = window & (fsd > 0)
        if ok.any():
            ratio = float(np.sqrt(np.mean(rms[ok] ** 2) / np.mean(fsd[ok] ** 2)))
            b.text(0.98, 0.6, "MC RMS / filter sigma = %.2f\n(t = %g-%g s)"
                   % (ratio, t[ok][0], t[ok][-1]), transform=b.transAxes, ha="right", va="center",
                   fontsize=9, bbox=dict(fc="white", ec="0.6", alpha=0.9))
        for ax_ in (a, b):
            ax_.axvline(switch_t, color="green", lw=1.2, ls="--")
            ax_.axvspan(switch_t, t[-1], color="green", alpha=0.05, lw=0)
    axes[0, 0].legend(fontsize=8, loc="lower right")
    axes[0, 1].legend(fontsize=8, loc="upper center")
    axes[0, 0].set_title("bias-estimate error: mean (should stay inside +-sigma)", fontsize=10)
    axes[0, 1].set_title("spread: Monte-Carlo RMS vs the filter's own sigma", fontsize=10)
    for b in axes[2]:
        b.set_xlabel("flight time [s]  (green: after the %g s switch the estimate is frozen)"
                     % switch_t)
        b.set_xlim(t[0], t[-1])
    fig.suptitle("Fig. 4: radar bias estimate minus the true radar systematic error, per channel "
                 "(%s realizations, seed %s)" % (t2.get("realizations"), t2.get("seed")),
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def fig_readme(rs, ts, t2, switch_t, path, toi_is_apoi_before=True):
    toi_lab = ("TOI (compensated; = APOI before the switch)" if toi_is_apoi_before
               else "TOI (compensated)")
    r_mid = 0.5 * (rs["range_lo_m"] + rs["range_hi_m"]) / 1000.0
    order = np.argsort(r_mid)
    r_mid = r_mid[order]
    r_switch = range_at_time(ts["t_s"], ts["range_m"], switch_t) / 1000.0
    r_max = max(r_mid.max(), 1.0) + 0.5
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.1), sharex=True)
    for k, c in enumerate(COORDS):
        a = axes[k]
        a.axvspan(0, r_switch, color="green", alpha=0.06, lw=0)
        a.axvline(r_switch, color="green", ls="--", lw=1.1,
                  label="switch at %g s: compensation from here on" % switch_t)
        a.axhline(0, color="0.4", lw=0.7)
        a.plot(r_mid, rs["toi_mean_%s_m" % c][order], color=C_TOI, lw=3.0, alpha=0.9,
               label=toi_lab)
        a.plot(r_mid, rs["apoi_mean_%s_m" % c][order], color=C_APOI, lw=1.5,
               label="APOI (raw plots)")
        for row, mk in (("APOI", "*"), ("TOI", "P")):
            for j, (r, mean, se, paper) in enumerate(t2[row]):
                if paper is not None:
                    tt = table_time(ts, r)
                    if tt is None:
                        continue
                    a.plot([range_at_time(ts["t_s"], ts["range_m"], tt) / 1000], [paper[k]], marker=mk, ms=10, color=C_PAPER, ls="none",
                           label="paper Table 2, %s" % row if j == 0 else None, zorder=5)
        a.set_title("coordinate %s" % COORD_NAME[c], fontsize=10)
        a.set_xlabel("slant range from the radar [km] (approach: left to right)", fontsize=9)
        a.grid(alpha=0.3)
        a.set_xlim(r_max, 0)
    axes[0].set_ylabel("systematic error (ensemble mean) [m]")
    h, l = axes[0].get_legend_handles_labels()
    fig.suptitle("Landing-radar systematic error before (APOI) and after (TOI) compensation "
                 "with the bias estimated from SNS/INS data; %s realizations, 1 km range bins"
                 % t2.get("realizations"), fontsize=10.5)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    fig.legend(h, l, loc="lower center", ncol=5, fontsize=8.5, framealpha=0.95)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def read_scenario(path):
    """Read the run's scenario.json -> the keys the geometry figure needs, or None if absent."""
    if not os.path.isfile(path):
        return None
    doc = load_json(path)
    out = {}
    for sec, key in (("radar", "x_m"), ("radar", "z_m"), ("radar", "antenna_height_m"),
                     ("prl_bias", "switch_time_s"), ("logger", "table_ranges_m"),
                     ("logger", "table_range_origin"), ("prl", "max_range_m")):
        if not isinstance(doc, dict) or not isinstance(doc.get(sec), dict) or key not in doc[sec]:
            raise InputError("%s: missing key %s.%s" % (path, sec, key))
        out["%s.%s" % (sec, key)] = doc[sec][key]
    return out


def fig_geometry(ts, sc, switch_t, t2, path):
    """The approach in the landing frame L: plan view (seen from above) and vertical profile,
    the radar site with range rings, the Table 2 ranges, and the estimation/compensation
    switch."""
    t = ts["t_s"]
    x, y, z = (ts["aircraft_%s_m" % c] / 1000.0 for c in ("x", "y", "z"))
    rx, rz = sc["radar.x_m"] / 1000.0, sc["radar.z_m"] / 1000.0
    sx, sy, sz = (float(np.interp(switch_t, t, v)) for v in (x, y, z))
    fig, (ax, axp) = plt.subplots(2, 1, figsize=(11, 8.2), gridspec_kw={"height_ratios": [2.4, 1]})
    # Plan view. With x decreasing to the right (the aircraft flies left to right, as in the
    # other figures) and z up, the picture is seen from above (z = x cross y, y up).
    pad = 1.0
    x_hi, x_lo = max(x.max(), rx) + pad, min(x.min(), rx, 0.0) - pad
    z_lo, z_hi = min(z.min(), rz, 0.0) - pad, max(z.max(), rz, 0.0) + pad
    d_max = math.hypot(max(x_hi - rx, rx - x_lo), max(z_hi - rz, rz - z_lo))
    step = 5 if d_max > 12 else 2
    a = np.linspace(0, 2 * math.pi, 721)
    for k, r in enumerate(np.arange(step, d_max + step, step)):
        ax.plot(rx + r * np.cos(a), rz + r * np.sin(a), color="0.6", lw=0.7, ls="--",
                label="range rings around the radar (horizontal), every %g km" % step if k == 0 else None)
        # label where the ring meets the top edge (far side from the runway), else the bottom
        for zl in (z_hi - 0.35 * pad, z_lo + 0.35 * pad):
            if r > abs(zl - rz) and x_lo < rx + math.sqrt(r * r - (zl - rz) ** 2) < x_hi:
                ax.text(rx + math.sqrt(r * r - (zl - rz) ** 2), zl, "%g km" % r, fontsize=7.5, color="0.4",
                        ha="center", va="center", clip_on=True, bbox=dict(fc="white", ec="none", alpha=0.85, pad=0.5))
                break
    cx, cz = (rx, rz) if sc["logger.table_range_origin"] == "radar" else (0.0, 0.0)
    for k, r in enumerate(sc["logger.table_ranges_m"]):
        ax.plot(cx + r / 1000.0 * np.cos(a), cz + r / 1000.0 * np.sin(a), color="tab:orange", lw=1.0, ls=":",
                label="Table 2 ranges (from the %s) and where the aircraft is there"
                % sc["logger.table_range_origin"] if k == 0 else None)
        tt = table_time(ts, r)
        if tt is not None:
            px, pz = float(np.interp(tt, t, x)), float(np.interp(tt, t, z))
            ax.plot([px], [pz], "o", color="tab:orange", ms=6, zorder=5)
            ax.annotate("%g km" % (r / 1000.0), (px, pz), textcoords="offset points", xytext=(5, 6), fontsize=8.5,
                        color="tab:orange")
    ax.plot([x_hi, x_lo], [0, 0], color="0.3", lw=0.8, ls="-.", label="runway axis (z = 0)")
    ax.plot(x, z, color="tab:blue", lw=2, label="aircraft path (true), t = %g ... %g s" % (t[0], t[-1]))
    ax.plot([x[0]], [z[0]], ">", color="tab:blue", ms=8)
    ax.plot([0], [0], "s", color="black", ms=6, label="runway threshold (origin of L)")
    ax.plot([rx], [rz], "^", color="tab:red", ms=9,
            label="radar site (x %g m, z %g m)" % (sc["radar.x_m"], sc["radar.z_m"]))
    ax.plot([sx], [sz], "*", color="green", ms=15, zorder=6,
            label="switch at %g s: estimation before, compensation after" % switch_t)
    ax.annotate("switch %g s" % switch_t, (sx, sz), textcoords="offset points", xytext=(6, 8), fontsize=9,
                color="green")
    ax.set_aspect("equal")
    ax.set_xlim(x_hi, x_lo)
    ax.set_ylim(z_lo, z_hi)
    ax.set_xlabel("x: along the runway axis, away from the runway [km]")
    ax.set_ylabel("z: lateral [km]")
    ax.set_title("Approach geometry in the landing frame L, seen from above; %s realizations, seed %s"
                 % (t2.get("realizations"), t2.get("seed")), fontsize=11)
    ax.grid(alpha=0.25)

    # Vertical profile.
    axp.plot(x, y * 1000.0, color="tab:blue", lw=2)
    axp.plot([sx], [sy * 1000.0], "*", color="green", ms=15, zorder=6)
    axp.plot([rx], [sc["radar.antenna_height_m"]], "^", color="tab:red", ms=9)
    axp.plot([0], [0], "s", color="black", ms=6)
    for r in sc["logger.table_ranges_m"]:
        tt = table_time(ts, r)
        if tt is not None:
            axp.plot([np.interp(tt, t, x)], [np.interp(tt, t, y) * 1000.0], "o", color="tab:orange", ms=6)
    axp.set_xlim(x_hi, x_lo)
    axp.set_ylim(min(0.0, y.min() * 1000.0) - 30, y.max() * 1000.0 * 1.15 + 10)
    axp.set_xlabel("x: along the runway axis, away from the runway [km]")
    axp.set_ylabel("y: height above the threshold [m]")
    axp.set_title("vertical profile", fontsize=9)
    axp.grid(alpha=0.25)
    h, l = ax.get_legend_handles_labels()
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.legend(h, l, loc="lower center", ncol=2, fontsize=8.5, framealpha=0.95)
    fig.savefig(path, dpi=100)
    plt.close(fig)


# ----------------------------------------------------------------------------- main


_JOBS = []


def _draw(i):
    fn, fargs, _ = _JOBS[i]
    fn(*fargs)


def draw_all(jobs):
    """Draw the figures, one process per core (forked: each gets the data as it is; matplotlib
    renders a figure in about half a second, so the six of a run take ~3 s on one core). The PNGs
    are the same whichever process draws them. A drawing process that dies (killed, out of
    memory) fails the plotting with BrokenProcessPool, where multiprocessing.Pool would wait for
    it for ever."""
    global _JOBS
    _JOBS = jobs
    n = min(len(jobs), os.cpu_count() or 1)
    if n <= 1:
        for i in range(len(jobs)):
            _draw(i)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    with ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("fork")) as pool:
        list(pool.map(_draw, range(len(jobs))))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="output directory of rnav_inproc / rnav_logger")
    ap.add_argument("--switch-time", type=float, default=None,
                    help="estimation->compensation switch [s]; default: column switch_time_s of "
                         "stats_time.csv if present, else prl_bias.switch_time_s of DIR/scenario.json, "
                         "else 400")
    ap.add_argument("--smooth", type=float, default=15.0,
                    help="running-mean window for the mean-error curves [s] (default 15)")
    args = ap.parse_args(argv)
    load_plotting()
    d = args.dir
    try:
        ts = read_csv(os.path.join(d, "stats_time.csv"), TIME_COLS)
        rs = read_csv(os.path.join(d, "stats_range.csv"), RANGE_COLS)
        t2 = read_table2(os.path.join(d, "table2_detail.json"))
        sc = read_scenario(os.path.join(d, "scenario.json"))
    except InputError as e:
        print("%s: error: %s" % (PROG, e), file=sys.stderr)
        return 2
    if len(ts["t_s"]) < 2 or np.any(np.diff(ts["t_s"]) <= 0):
        print("%s: error: %s: t_s must increase strictly over at least two rows"
              % (PROG, os.path.join(d, "stats_time.csv")), file=sys.stderr)
        return 2

    if args.switch_time is not None:
        switch_t = args.switch_time
    elif "switch_time_s" in ts:
        switch_t = float(ts["switch_time_s"][0])
    elif sc is not None:
        switch_t = float(sc["prl_bias.switch_time_s"])
    else:
        switch_t = 400.0
    inferred = infer_switch_time(ts)
    if inferred is None:
        print("%s: note: TOI equals APOI everywhere (no compensation in this run)" % PROG,
              file=sys.stderr)
    elif abs(inferred - switch_t) > 1.5 * float(np.median(np.diff(ts["t_s"]))):
        print("%s: warning: switch time %g s, but TOI first differs from APOI at %g s "
              "(compensate_during_estimation, or pass --switch-time)"
              % (PROG, switch_t, inferred), file=sys.stderr)

    before = ts["t_s"] < switch_t
    toi_is_apoi_before = bool(all(np.allclose(ts["toi_mean_%s_m" % c][before],
                                              ts["apoi_mean_%s_m" % c][before], atol=1e-9)
                                  for c in COORDS))
    jobs = []  # (function, arguments, the PNG it writes)
    for k, c in enumerate(COORDS):
        p = os.path.join(d, "fig%d_%s.png" % (k + 1, c))
        jobs.append((fig_coordinate, (k + 1, k, c, ts, t2, switch_t, args.smooth, p, toi_is_apoi_before), p))
    p = os.path.join(d, "fig4_bias.png")
    jobs.append((fig_bias, (ts, t2, switch_t, p), p))
    p = os.path.join(d, "readme_figure.png")
    jobs.append((fig_readme, (rs, ts, t2, switch_t, p, toi_is_apoi_before), p))
    if sc is None or "aircraft_x_m" not in ts:
        print("%s: note: no geometry.png (needs scenario.json and the aircraft_*_m columns of "
              "stats_time.csv, written by this version's logger)" % PROG, file=sys.stderr)
    else:
        p = os.path.join(d, "geometry.png")
        jobs.append((fig_geometry, (ts, sc, switch_t, t2, p), p))
    draw_all(jobs)
    written = [p for _, _, p in jobs]
    for p in written:
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
