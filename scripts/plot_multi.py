#!/usr/bin/python3
"""Residual plot of a multi-sensor diagnosis: one panel per sensor:target, bearing residual
(measured minus reference) [deg] against time with the extended model's fit, the estimation /
held-out split marked. Recordings diagnosed together (a non-empty recording column): one figure
per recording, OUT with _<recording> before its extension. With --report (the diagnosis's JSON),
each panel's legend names the effects acting on its sensor:target with their estimates.
Usage: plot_multi.py RESIDUALS.csv OUT.png [TITLE] [--report REPORT.json]"""
import sys as _sys

from rnav.cli_args import doc_help

doc_help(__doc__, _sys.argv)  # before matplotlib: the help needs neither it nor numpy
import os
import csv
import json
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from plot_gaps import broken  # noqa: E402  (lines break at data gaps)
from rnav.effect_labels import legend  # noqa: E402  (the effects named, with their estimates)


def main():
    args, report = list(sys.argv[1:]), None
    if "--report" in args:
        i = args.index("--report")
        if i + 1 >= len(args):
            sys.exit("plot_multi: --report needs a FILE")
        try:
            with open(args[i + 1]) as f:
                report = json.load(f)
        except (OSError, ValueError) as e:
            sys.exit("plot_multi: %s: %s" % (args[i + 1], e))
        del args[i:i + 2]
    if len(args) < 2:
        sys.exit(__doc__)
    sys.argv = [sys.argv[0]] + args
    by_rec = {}
    with open(sys.argv[1], newline="") as f:
        for r in csv.DictReader(f):
            if r["quantity"] != "bearing":
                continue
            by_rec.setdefault(r.get("recording") or "", {}).setdefault(f"{r['sensor']}:{r['target']}", []).append(r)
    if not by_rec:
        sys.exit(f"plot_multi: no bearing rows in {sys.argv[1]}")
    base, ext = os.path.splitext(sys.argv[2])
    for rec, rows in sorted(by_rec.items()):
        title = sys.argv[3] if len(sys.argv) > 3 else "multi-sensor diagnosis (dotted: held-out window starts)"
        plot(rows, sys.argv[2] if rec == "" else f"{base}_{rec}{ext}", title if rec == "" else f"{rec}: {title}",
             report, rec or None)


def plot(rows, out_png, title, report=None, recording=None):
    keys = sorted(rows)
    t0 = min(float(r["t_s"]) for k in keys for r in rows[k])
    cols = 2
    nrow = math.ceil(len(keys) / cols)
    fig, axes = plt.subplots(nrow, cols, figsize=(11, 2.3 * nrow), sharex=True, squeeze=False)
    for ax, k in zip(axes.flat, keys):
        rr = rows[k]
        t = [float(r["t_s"]) - t0 for r in rr]
        y = [math.degrees(float(r["residual"])) for r in rr]
        fit = [math.degrees(float(r["extended_fit"])) for r in rr]
        out = [r["outlier"] == "1" for r in rr]
        ax.plot([a for a, o in zip(t, out) if not o], [b for b, o in zip(y, out) if not o], ".", ms=2, color="0.5",
                label="residual")
        ax.plot([a for a, o in zip(t, out) if o], [b for b, o in zip(y, out) if o], "x", ms=3, color="tab:red",
                label="outlier")
        # the fit, broken across data gaps (plot_gaps: over 3x the median step)
        sensor, _, target = k.partition(":")
        ax.plot(*broken(t, fit), "-", color="tab:blue", lw=1.2, label=legend(report, sensor, target, recording, quantity="bearing"))
        split = [a for a, r in zip(t, rr) if r["estimation"] == "0"]
        if split:
            ax.axvline(min(split), color="k", ls=":", lw=0.8)
        ax.set_title(k, fontsize=9)
        ax.set_ylabel("bearing [deg]", fontsize=8)
        lim = sorted(abs(v) for v in y)[int(0.98 * (len(y) - 1))] * 1.3 + 0.1
        ax.set_ylim(-lim, lim)
    for ax in axes.flat[len(keys):]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel("time since first detection [s]")
    if report:
        for ax in axes.flat[:len(keys)]:
            ax.legend(fontsize=6, loc="best")
    else:
        axes.flat[0].legend(fontsize=7, loc="upper right")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
