#!/usr/bin/python3
"""Draw a scene validation (rnav_scene validate --json): per sensor:target pair a row of panels,
one per statistic, each the simulations' 5-95 % band per model (nominal grey, extended blue) and
the recording's value (a red dot where it lies outside the extended band, else black).

usage: plot_validate.py VALIDATION.json OUT.png
"""
import sys as _sys

from rnav.cli_args import doc_help

doc_help(__doc__, _sys.argv)  # before matplotlib: the help needs neither it nor numpy
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = [("bearing", "mean"), ("bearing", "sd"), ("bearing", "lag1"),
           ("range", "mean"), ("range", "sd"), ("range", "lag1"), ("detection", "detection_rate")]


def shown(row, x):
    if x is None:
        return None
    return x * 180 / math.pi if row["quantity"] == "bearing" and row["statistic"] in ("mean", "sd") else x


def unit(q, s):
    if s in ("lag1", "detection_rate"):
        return ""
    return " [deg]" if q == "bearing" else " [m]"


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    with open(argv[1]) as f:
        v = json.load(f)
    rows = v["rows"]
    pairs = sorted({r["pair"] for r in rows})
    cols = [c for c in COLUMNS if any(r["quantity"] == c[0] and r["statistic"] == c[1] for r in rows)]
    fig, axes = plt.subplots(len(pairs), len(cols), figsize=(2.3 * len(cols), 0.9 * len(pairs) + 1.2), squeeze=False)
    for i, p in enumerate(pairs):
        for j, (q, s) in enumerate(cols):
            ax = axes[i][j]
            sel = [r for r in rows if r["pair"] == p and r["quantity"] == q and r["statistic"] == s]
            ax.set_yticks([])
            if i == 0:
                ax.set_title(("detection rate" if s == "detection_rate" else q + " " + s) + unit(q, s), fontsize=8)
            if j == 0:
                ax.set_ylabel(p, fontsize=7, rotation=0, ha="right", va="center")
            ax.tick_params(labelsize=6)
            if not sel:
                ax.set_axis_off()
                continue
            for k, model in enumerate(("nominal", "extended")):
                for r in sel:
                    if r["model"] != model or r["band_lo"] is None:
                        continue
                    ax.plot([shown(r, r["band_lo"]), shown(r, r["band_hi"])], [k, k], lw=5,
                            color="0.7" if model == "nominal" else "tab:blue", solid_capstyle="butt")
            real = sel[0]
            ext = [r for r in sel if r["model"] == "extended"] or sel
            ax.plot([shown(real, real["real"])] * 2, [-0.5, 1.5], color="red" if not ext[0]["inside"] else "black", lw=1)
            ax.set_ylim(-0.7, 1.7)
    fig.suptitle("%s: the recording (line) against %d simulations per model (grey nominal, blue extended; "
                 "red: outside the extended band)" % (v["recording"], v["runs"]), fontsize=9)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=90)


if __name__ == "__main__":
    main(sys.argv)
