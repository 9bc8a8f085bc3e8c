#!/usr/bin/python3
"""Figures for the azimuth-only (UAV) ensemble written by rnav_inproc / rnav_uav_logger.

Usage:  /usr/bin/python3 scripts/plot_uav.py DIR

Reads DIR/uav_stats_time.csv (columns: see loggers/uav_stats.cpp) and DIR/summary.json (for the
evaluation time, the run count and the seed) and writes into DIR:

  uav_rmse.png      position and velocity RMSE of every estimator against time, with the PCRB
                    (log y), the evaluation time (default: after two orbits) marked.
  uav_nees.png      mean NEES (4 dof) of every estimator against time with the 95 % chi-square
                    band for the run count (log y); below, mean NIS (1 dof) with its band.
  uav_overview.png  compact figure for the README: position RMSE vs PCRB, and NEES with band.
  geometry.png      plan view of one realization from DIR/track.csv (scripts/plot_uav_geometry.py):
                    UAV path, the object's true track, the estimate tracks, and at a few times the
                    estimates with their 2-sigma (86.5 %) ellipses and the measured bearing ray.
                    Drawn when DIR/scenario.json's logger.track_realization is >= 0 (then
                    track.csv must exist); skipped with a note for an output without scenario.json.

NaN (or inf) cells in the CSV, e.g. the NIS before the first update, are treated as missing.
Needs Debian's python3 with python3-numpy and python3-matplotlib (Agg backend, no display).
Exit code 2 with a message naming the file, line and column when an input is missing or
malformed.
"""
import sys as _sys

from rnav.cli_args import doc_help

doc_help(__doc__, _sys.argv)  # before matplotlib: the help needs neither it nor numpy

import csv
import json
import math
import os
import re
import sys

from rnav import figures

PROG = "plot_uav.py"
plt = figures.pyplot(PROG)
import numpy as np  # noqa: E402  (after figures.pyplot: it checks numpy and matplotlib, sets Agg)
import plot_uav_geometry  # noqa: E402

CSV_NAME = "uav_stats_time.csv"
SUMMARY_NAME = "summary.json"
BASE_COLS = ("t_s", "pcrb_pos_m", "pcrb_vel_mps", "nees_band_lo", "nees_band_hi",
             "nis_band_lo", "nis_band_hi")
EST_SUFFIXES = ("_n", "_rmse_pos_m", "_rmse_vel_mps", "_nees_mean", "_nis_mean")
# Known estimators first, in this order, with their labels and colours; others follow.
EST_STYLE = {
    "ekf": ("Cartesian EKF (paper)", "#d62728"),
    "rpekf": ("range-parameterised EKF bank", "#1f77b4"),
    "ml": ("batch MAP (all bearings)", "#2ca02c"),
    "pf": ("particle filter", "#ff7f0e"),
}
OTHER_COLOURS = ("#9467bd", "#8c564b", "#e377c2", "#7f7f7f")
C_PCRB = "black"
C_BAND = "#9e9e9e"
C_EVAL = "#555555"

InputError = figures.InputError


# ----------------------------------------------------------------------------- input


def parse_cell(path, lineno, colno, name, cell):
    """One CSV cell -> float; NaN/inf -> nan (missing); anything else non-numeric: InputError."""
    s = cell.strip()
    try:
        v = float(s)
    except ValueError:
        raise InputError("%s: line %d, column %d (%s): '%s' is not a number"
                         % (path, lineno, colno, name, cell)) from None
    if not math.isfinite(v):
        return float("nan"), math.isinf(v)
    return v, False


def read_stats_csv(path):
    """Read uav_stats_time.csv -> (columns {name: np.array}, estimator names, #inf cells)."""
    if not os.path.isfile(path):
        raise InputError("%s: file not found" % path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError("%s: cannot read: %s" % (path, e)) from None
    if not rows or not any(c.strip() for c in rows[0]):
        raise InputError("%s: line 1: empty (expected the header line)" % path)
    header = [h.strip() for h in rows[0]]
    for i, h in enumerate(header, start=1):
        if not h:
            raise InputError("%s: line 1, column %d: empty column name" % (path, i))
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise InputError("%s: line 1: duplicate column(s) %s" % (path, ", ".join(dup)))
    missing = [c for c in BASE_COLS if c not in header]
    if missing:
        raise InputError("%s: line 1: header lacks column(s) %s" % (path, ", ".join(missing)))
    names = []
    for h in header:
        m = re.fullmatch(r"(.+)_rmse_pos_m", h)
        if m and m.group(1) not in names:
            names.append(m.group(1))
    if not names:
        raise InputError("%s: line 1: no estimator columns (NAME_rmse_pos_m)" % path)
    for n in names:
        lack = [n + s for s in EST_SUFFIXES if n + s not in header]
        if lack:
            raise InputError("%s: line 1: estimator '%s' lacks column(s) %s"
                             % (path, n, ", ".join(lack)))
    data, n_inf = [], 0
    for lineno, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue  # blank line (e.g. a trailing newline)
        if len(row) != len(header):
            raise InputError("%s: line %d: %d fields, the header has %d"
                             % (path, lineno, len(row), len(header)))
        vals = []
        for colno, (name, cell) in enumerate(zip(header, row), start=1):
            v, was_inf = parse_cell(path, lineno, colno, name, cell)
            n_inf += was_inf
            if name == "t_s" and not math.isfinite(v):
                raise InputError("%s: line %d, column %d (t_s): '%s': the time must be finite"
                                 % (path, lineno, colno, cell))
            if name.endswith("_n") and name[:-2] in names and math.isfinite(v) and (
                    v < 0 or v != int(v)):
                raise InputError("%s: line %d, column %d (%s): '%s' is not a run count"
                                 % (path, lineno, colno, name, cell))
            vals.append(v)
        if data and not vals[header.index("t_s")] > data[-1][header.index("t_s")]:
            raise InputError("%s: line %d, column %d (t_s): time %s does not increase"
                             % (path, lineno, header.index("t_s") + 1, row[header.index("t_s")]))
        data.append(vals)
    if not data:
        raise InputError("%s: no data rows after the header" % path)
    arr = np.array(data, dtype=float)
    cols = {name: arr[:, i] for i, name in enumerate(header)}
    order = [n for n in EST_STYLE if n in names] + [n for n in names if n not in EST_STYLE]
    return cols, order, n_inf


def read_summary(path):
    """summary.json -> dict with eval_time_s (required), realizations, seed (optional)."""
    if not os.path.isfile(path):
        raise InputError("%s: file not found (needed for the evaluation time)" % path)
    try:
        with open(path) as f:
            doc = json.load(f)
    except json.JSONDecodeError as e:
        raise InputError("%s: line %d, column %d: invalid JSON: %s"
                         % (path, e.lineno, e.colno, e.msg)) from None
    except (OSError, UnicodeDecodeError) as e:
        raise InputError("%s: cannot read: %s" % (path, e)) from None
    if not isinstance(doc, dict):
        raise InputError("%s: line 1, column 1: expected a JSON object" % path)
    out = {}
    et = doc.get("eval_time_s")
    if not isinstance(et, (int, float)) or isinstance(et, bool) or not math.isfinite(et):
        raise InputError("%s: key 'eval_time_s': expected a finite number, got %r" % (path, et))
    out["eval_time_s"] = float(et)
    for k in ("realizations", "seed"):
        v = doc.get(k)
        out[k] = v if isinstance(v, int) and not isinstance(v, bool) else None
    out["estimators"] = doc.get("estimators") if isinstance(doc.get("estimators"), dict) else {}
    out["pcrb_pos_m"] = doc.get("pcrb_pos_m")
    return out


# ----------------------------------------------------------------------------- helpers


def style(name, i):
    if name in EST_STYLE:
        return EST_STYLE[name]
    return name, OTHER_COLOURS[i % len(OTHER_COLOURS)]


def value_at(t, y, t0):
    """The last finite y at or before t0 (as the summary takes it), else nan."""
    ok = (t <= t0 + 1e-9) & np.isfinite(y)
    return y[ok][-1] if ok.any() else float("nan")


def log_limits(curves, skip_first=()):
    """y-limits for a log axis that show every curve; arrays in skip_first lose their first
    sample for the upper limit (the PCRB's prior can be singular at the first bearing)."""
    lo, hi = [], []
    for y in curves:
        pos = y[np.isfinite(y) & (y > 0)]
        if pos.size:
            lo.append(pos.min())
    for y in list(curves) + list(skip_first):
        yy = y[1:] if any(y is s for s in skip_first) else y
        pos = yy[np.isfinite(yy) & (yy > 0)]
        if pos.size:
            hi.append(pos.max())
    if not lo or not hi:
        return None
    return min(lo) / 1.6, max(hi) * 1.6


def fmt(v, unit=""):
    if not math.isfinite(v):
        return "n/a"
    a = abs(v)
    s = ("%.3g" % v) if (a >= 1e4 or a < 1e-2) else ("%.3f" % v if a < 10 else "%.1f" % v)
    return s + unit


def mark_eval(ax, t_eval, label=True):
    ax.axvline(t_eval, color=C_EVAL, ls="--", lw=1.0, zorder=1)
    if label:
        ax.annotate("evaluation time %.1f s" % t_eval, xy=(t_eval, 0.5),
                    xycoords=("data", "axes fraction"), xytext=(-3, 0), textcoords="offset points",
                    ha="right", va="center", rotation=90, fontsize=8, color=C_EVAL)


def xlim(t, t_eval):
    """Time limits with a small margin, so an evaluation line at the last sample stays visible."""
    lo, hi = float(t[0]), float(max(t[-1], t_eval))
    pad = 0.015 * (hi - lo) if hi > lo else 1.0
    return lo, hi + pad


def set_log_y(ax, lim):
    ax.set_yscale("log")
    if lim:
        ax.set_ylim(*lim)
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)


def runs_text(summ, n):
    s = "%d realizations" % n if n else "realizations: ?"
    if summ.get("seed") is not None:
        s += ", seed %d" % summ["seed"]
    return s


# ----------------------------------------------------------------------------- figures


def fig_rmse(c, names, summ, n_runs, path):
    t, te = c["t_s"], summ["eval_time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(9.5, 7.6), sharex=True)
    for ax, key, pkey, unit, title in (
            (axes[0], "_rmse_pos_m", "pcrb_pos_m", " m", "position RMSE [m]"),
            (axes[1], "_rmse_vel_mps", "pcrb_vel_mps", " m/s", "velocity RMSE [m/s]")):
        curves = []
        for i, n in enumerate(names):
            lab, col = style(n, i)
            y = c[n + key]
            curves.append(y)
            ax.plot(t, y, color=col, lw=1.3,
                    label="%s  (%s at t_eval)" % (lab, fmt(value_at(t, y, te), unit)))
        p = c[pkey]
        ax.plot(t, p, color=C_PCRB, lw=1.1, ls=(0, (4, 2)),
                label="PCRB  (%s at t_eval)" % fmt(value_at(t, p, te), unit))
        set_log_y(ax, log_limits(curves, skip_first=(p,)))
        mark_eval(ax, te)
        ax.set_ylabel(title)
        ax.legend(loc="best", fontsize=8.5, framealpha=0.9)
    axes[1].set_xlabel("time since start [s]")
    axes[1].set_xlim(*xlim(t, te))
    fig.suptitle("Azimuth-only estimation of the surface object: RMSE vs PCRB (%s)"
                 % runs_text(summ, n_runs), fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def band_fill(ax, t, lo, hi, label):
    ok = np.isfinite(lo) & np.isfinite(hi)
    ax.fill_between(t[ok], lo[ok], hi[ok], color=C_BAND, alpha=0.35, lw=0, label=label, zorder=0)


def consistency_panel(ax, c, t, te, names, n_runs, kind, dof, expected, **line):
    """One panel of fig_nees: each estimator's mean `kind` ("nees" or "nis") against the 95 %
    band of the mean of n_runs chi2(dof) and its expected value dof, on a log scale."""
    lo, hi = c[kind + "_band_lo"], c[kind + "_band_hi"]
    band_fill(ax, t, lo, hi,
              "95 %% band of the mean of %s chi2(%d)  [%s, %s]"
              % (n_runs or "?", dof, fmt(value_at(t, lo, te)), fmt(value_at(t, hi, te))))
    ax.axhline(float(dof), color="black", lw=0.8, ls=":", label=expected)
    curves = [lo, hi]
    for i, n in enumerate(names):
        lab, col = style(n, i)
        y = c[n + "_" + kind + "_mean"]
        curves.append(y)
        ax.plot(t, y, color=col, label="%s  (%s at t_eval)" % (lab, fmt(value_at(t, y, te))), **line)
    set_log_y(ax, log_limits(curves))


def fig_nees(c, names, summ, n_runs, path):
    t, te = c["t_s"], summ["eval_time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(9.5, 7.6), sharex=True)
    ax = axes[0]
    consistency_panel(ax, c, t, te, names, n_runs, "nees", 4, "expected value 4 (state dim.)", lw=1.2)
    mark_eval(ax, te)
    ax.set_ylabel("mean NEES (position + velocity)")
    ax.legend(loc="best", fontsize=8.5, framealpha=0.9)

    ax = axes[1]
    consistency_panel(ax, c, t, te, names, n_runs, "nis", 1, "expected value 1", lw=0.9, alpha=0.85)
    mark_eval(ax, te, label=False)
    ax.set_ylabel("mean NIS (bearing innovation)")
    ax.set_xlabel("time since start [s]")
    ax.set_xlim(*xlim(t, te))
    ax.legend(loc="best", fontsize=8.5, framealpha=0.9)
    fig.suptitle("Consistency of the azimuth-only estimators (%s)" % runs_text(summ, n_runs),
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig_overview(c, names, summ, n_runs, path):
    t, te = c["t_s"], summ["eval_time_s"]
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 3.9))
    ax = axes[0]
    curves = []
    for i, n in enumerate(names):
        lab, col = style(n, i)
        y = c[n + "_rmse_pos_m"]
        curves.append(y)
        ax.plot(t, y, color=col, lw=1.3, label="%s: %s" % (n, fmt(value_at(t, y, te), " m")))
    p = c["pcrb_pos_m"]
    ax.plot(t, p, color=C_PCRB, lw=1.1, ls=(0, (4, 2)), label="PCRB: %s" % fmt(value_at(t, p, te), " m"))
    set_log_y(ax, log_limits(curves, skip_first=(p,)))
    mark_eval(ax, te, label=False)
    ax.set_xlim(*xlim(t, te))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("position RMSE [m]")
    ax.set_title("position error (values at t_eval = %.0f s)" % te, fontsize=10)
    ax.legend(loc="best", fontsize=8.5, framealpha=0.9)

    ax = axes[1]
    band_fill(ax, t, c["nees_band_lo"], c["nees_band_hi"], "95 % band")
    curves = [c["nees_band_lo"], c["nees_band_hi"]]
    for i, n in enumerate(names):
        lab, col = style(n, i)
        y = c[n + "_nees_mean"]
        curves.append(y)
        ax.plot(t, y, color=col, lw=1.1, label="%s: %s" % (n, fmt(value_at(t, y, te))))
    set_log_y(ax, log_limits(curves))
    mark_eval(ax, te, label=False)
    ax.set_xlim(*xlim(t, te))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mean NEES (4 dof)")
    ax.set_title("consistency (%s)" % runs_text(summ, n_runs), fontsize=10)
    ax.legend(loc="best", fontsize=8.5, framealpha=0.9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


# ----------------------------------------------------------------------------- main


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr if len(argv) != 2 else sys.stdout)
        return 0 if len(argv) == 2 else 2
    d = argv[1]
    if not os.path.isdir(d):
        raise InputError("%s: not a directory" % d)
    cols, names, n_inf = read_stats_csv(os.path.join(d, CSV_NAME))
    summ = read_summary(os.path.join(d, SUMMARY_NAME))
    if n_inf:
        print("%s: note: %d infinite cell(s) in %s treated as missing" % (PROG, n_inf, CSV_NAME),
              file=sys.stderr)
    ns = [np.nanmax(cols[n + "_n"]) for n in names if np.isfinite(cols[n + "_n"]).any()]
    n_runs = summ.get("realizations") or (int(max(ns)) if ns else None)
    out = []
    for fname, fn in (("uav_rmse.png", fig_rmse), ("uav_nees.png", fig_nees),
                      ("uav_overview.png", fig_overview)):
        p = os.path.join(d, fname)
        fn(cols, names, summ, n_runs, p)
        out.append(p)
    p = geometry(d, summ)
    if p:
        out.append(p)
    for p in out:
        print(p)
    return 0


def geometry(d, summ):
    """Draw geometry.png if the run wrote a track (scenario.json's logger.track_realization >= 0)."""
    sc_path = os.path.join(d, "scenario.json")
    if not os.path.isfile(sc_path):
        print("%s: note: no geometry.png: %s is missing (an output of an older version?)" % (PROG, sc_path),
              file=sys.stderr)
        return None
    try:
        with open(sc_path) as f:
            sc = json.load(f)
    except json.JSONDecodeError as e:
        raise InputError("%s: line %d, column %d: invalid JSON: %s" % (sc_path, e.lineno, e.colno, e.msg)) from None
    except (OSError, UnicodeDecodeError) as e:
        raise InputError("%s: cannot read: %s" % (sc_path, e)) from None
    tr = sc.get("logger", {}).get("track_realization") if isinstance(sc, dict) else None
    if tr is None:
        print("%s: note: no geometry.png: %s has no logger.track_realization (an older version's output)"
              % (PROG, sc_path), file=sys.stderr)
        return None
    if not isinstance(tr, int) or isinstance(tr, bool):
        raise InputError("%s: key logger.track_realization: expected an integer, got %r" % (sc_path, tr))
    if tr < 0:
        return None
    track = os.path.join(d, plot_uav_geometry.TRACK_NAME)
    if not os.path.isfile(track):
        raise InputError("%s: file not found (logger.track_realization is %d in %s)" % (track, tr, sc_path))
    try:
        c, names = plot_uav_geometry.read_track(track)
    except plot_uav_geometry.TrackError as e:
        raise InputError(str(e)) from None
    order = [n for n in EST_STYLE if n in names] + [n for n in names if n not in EST_STYLE]
    styles = {n: style(n, i) for i, n in enumerate(order)}
    p = os.path.join(d, "geometry.png")
    plot_uav_geometry.fig_geometry(c, order, styles, summ, p)
    return p


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv))
    except InputError as e:
        print("%s: error: %s" % (PROG, e), file=sys.stderr)
        sys.exit(2)
