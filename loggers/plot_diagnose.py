#!/usr/bin/python3
"""Residuals of a landing-radar diagnosis: measured minus nav per channel against time, with
the nominal (constant bias) and the extended model's fits.
Usage: /usr/bin/python3 loggers/plot_diagnose.py residuals.csv out.png"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    path, out = argv[1], argv[2]
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
    t = cols["t_s"]
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    spec = [("range", "m", 1.0), ("course", "deg", 180 / math.pi), ("glide", "deg", 180 / math.pi)]
    for ax, (ch, unit, sc) in zip(axes, spec):
        key = "%s_%s" % (ch, "m" if ch == "range" else "rad")
        y = [v * sc for v in cols[key]]
        ax.plot(t, y, ".", ms=2, color="0.6", label="measured - nav")
        ax.plot(t, [v * sc for v in cols[key.replace("_m", "_nominal_m").replace("_rad", "_nominal_rad")]],
                color="tab:red", lw=1.5, label="nominal model (constant bias)")
        ax.plot(t, [v * sc for v in cols[key.replace("_m", "_extended_m").replace("_rad", "_extended_rad")]],
                color="tab:blue", lw=1.5, label="extended model")
        ax.set_ylabel("%s residual [%s]" % (ch, unit))
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("Landing radar: residuals against the nav solution, nominal vs extended model")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
