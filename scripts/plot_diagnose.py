#!/usr/bin/python3
"""Residuals of a diagnosis against time, with the nominal and the extended model's fits.
prl: measured minus nav per channel (range, course, glide); nominal = constant bias.
uav: bearing minus the reference (truth or fitted track); nominal = zero mean.
With the diagnosis's JSON report, the extended model's legend names each effect with its estimate.
Usage: /usr/bin/python3 scripts/plot_diagnose.py prl|uav residuals.csv out.png [report.json]"""
import sys as _sys

from rnav.cli_args import doc_help

doc_help(__doc__, _sys.argv)  # before matplotlib: the help needs neither it nor numpy
import csv
import json
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from plot_gaps import broken  # noqa: E402  (lines break at data gaps)
from rnav.effect_labels import legend  # noqa: E402  (the effects named, with their estimates)


def main(argv):
    if len(argv) not in (4, 5) or argv[1] not in ("prl", "uav"):
        print(__doc__, file=sys.stderr)
        return 2
    kind, path, out = argv[1], argv[2], argv[3]
    report = None
    if len(argv) == 5:
        try:
            with open(argv[4]) as f:
                report = json.load(f)
        except (OSError, ValueError) as e:
            print("plot_diagnose: %s: %s" % (argv[4], e), file=sys.stderr)
            return 2
    try:
        with open(path) as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        print("plot_diagnose: %s: %s" % (path, e), file=sys.stderr)
        return 2
    if not rows:
        print("plot_diagnose: %s: no data rows" % path, file=sys.stderr)
        return 2
    cols = {}
    for i, r in enumerate(rows, start=2):
        for k, v in r.items():
            try:
                x = float(v)
            except (TypeError, ValueError):
                print("plot_diagnose: %s:%d: column %s: '%s' is not a number" % (path, i, k, v), file=sys.stderr)
                return 2
            if not math.isfinite(x):
                print("plot_diagnose: %s:%d: column %s is not finite" % (path, i, k), file=sys.stderr)
                return 2
            cols.setdefault(k, []).append(x)
    need = ["t_s", "bearing_residual_rad", "bearing_extended_rad", "outlier"] if kind == "uav" else \
        ["t_s", "range_m", "range_nominal_m", "range_extended_m"]
    for k in need:
        if k not in cols:
            print("plot_diagnose: %s: no column '%s' (is it a %s diagnosis?)" % (path, k, kind), file=sys.stderr)
            return 2
    if kind == "uav":
        return plot_uav(cols, out, report)
    t = cols["t_s"]
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    spec = [("range", "m", 1.0), ("course", "deg", 180 / math.pi), ("glide", "deg", 180 / math.pi)]
    fit_label = legend(report)
    for ax, (ch, unit, sc) in zip(axes, spec):
        key = "%s_%s" % (ch, "m" if ch == "range" else "rad")
        y = [v * sc for v in cols[key]]
        ax.plot(t, y, ".", ms=2, color="0.6", label="measured - nav")
        ax.plot(*broken(t, [v * sc for v in cols[key.replace("_m", "_nominal_m").replace("_rad", "_nominal_rad")]]),
                color="tab:red", lw=1.5, label="nominal model (constant bias)")
        ax.plot(*broken(t, [v * sc for v in cols[key.replace("_m", "_extended_m").replace("_rad", "_extended_rad")]]),
                color="tab:blue", lw=1.5, label=fit_label)
        ax.set_ylabel("%s residual [%s]" % (ch, unit))
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("Landing radar: residuals against the nav solution, nominal vs extended model")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)
    return 0


def plot_uav(cols, out, report=None):
    t0 = cols["t_s"][0]
    t = [v - t0 for v in cols["t_s"]]
    deg = 180 / math.pi
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax = axes[0]
    inl = [i for i, o in enumerate(cols["outlier"]) if o == 0]
    out_i = [i for i, o in enumerate(cols["outlier"]) if o != 0]
    ax.plot([t[i] for i in inl], [cols["bearing_residual_rad"][i] * deg for i in inl], ".", ms=2, color="0.55",
            label="measured - reference bearing")
    if out_i:
        ax.plot([t[i] for i in out_i], [cols["bearing_residual_rad"][i] * deg for i in out_i], "x", ms=4,
                color="tab:orange", label="outliers")
    ax.axhline(0, color="tab:red", lw=1.5, label="nominal model (zero mean)")
    ax.plot(*broken(t, [v * deg for v in cols["bearing_extended_rad"]]), color="tab:blue", lw=1.5, label=legend(report))
    ax.set_ylabel("bearing residual [deg]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    # running RMS over 5 s windows shows noise level and its changes
    ax2 = axes[1]
    res = cols["bearing_residual_rad"]
    win, xs, ys = 5.0, [], []
    j = 0
    for i in range(len(t)):
        while t[j] < t[i] - win:
            j += 1
        seg = [res[k] * deg for k in range(j, i + 1)]
        xs.append(t[i])
        ys.append(math.sqrt(sum(v * v for v in seg) / len(seg)))
    ax2.plot(*broken(xs, ys), color="0.3", lw=1)
    ax2.set_ylabel("5 s RMS [deg]")
    ax2.set_xlabel("time from the first frame [s]")
    ax2.grid(alpha=0.3)
    fig.suptitle("Azimuth-only data: bearing residuals, nominal vs extended model")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
