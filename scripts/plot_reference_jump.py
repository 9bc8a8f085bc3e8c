#!/usr/bin/python3
"""Where a target's reference track jumped (a multi-sensor diagnosis's `reference_jumps`): a map
of the reference (north, east [m] from its position at the jump) within --window seconds of the
jump, the stretch the diagnosis used drawn solid and the rest dashed, with every range sensor's
detections in that window that lie within --near metres of the reference (the target's echoes,
unassociated); and below, the reference's speed between consecutive samples [m/s], where a jump
shows as a spike no boat makes.

Usage: plot_reference_jump.py REPORT.json OUT_PREFIX FOLDER [FOLDER...] [--window S] [--near M]
  FOLDER: the recordings' CSV folders as diagnosed (observer.csv, detections.csv, truth.csv;
  several: each named by its folder, as the diagnosis names them). One figure per jump:
  OUT_PREFIX_<target>.png (one recording) or OUT_PREFIX_<recording>_<target>.png; none when the
  report names no jump."""
import sys as _sys

from rnav.cli_args import doc_help

doc_help(__doc__, _sys.argv)  # before matplotlib: the help needs neither it nor numpy
import csv
import json
import math
import os
import sys

import matplotlib
import numpy
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

EARTH_M = 6371008.8  # mean Earth radius [m]: a local flat map within a few hundred metres


def die(msg):
    sys.exit("plot_reference_jump: " + msg)


def read_rows(path):
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except OSError as e:
        die("%s: %s" % (path, e))


def option(args, name, default):
    if name not in args:
        return default
    i = args.index(name)
    if i + 1 >= len(args):
        die("%s needs a value" % name)
    try:
        v = float(args[i + 1])
    except ValueError:
        die("%s: '%s' is not a number" % (name, args[i + 1]))
    if not v > 0:
        die("%s must be > 0" % name)
    del args[i:i + 2]
    return v


def main():
    args = sys.argv[1:]
    window = option(args, "--window", 30.0)
    near = option(args, "--near", 30.0)
    if len(args) < 3:
        die(__doc__)
    report_path, prefix, folders = args[0], args[1], args[2:]
    try:
        with open(report_path) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        die("%s: %s" % (report_path, e))
    if "reference_jumps" not in report:
        die("%s: no reference_jumps (not a multi-sensor diagnosis report)" % report_path)
    by_name = {"": folders[0]} if len(folders) == 1 else {os.path.basename(os.path.normpath(f)): f for f in folders}
    for j in report["reference_jumps"]:
        if j["recording"] not in by_name:
            die("%s: recording '%s' is none of the folders given" % (report_path, j["recording"]))
        out = "%s_%s%s.png" % (prefix, j["recording"] + "_" if j["recording"] else "", j["target"])
        plot(j, by_name[j["recording"]], out, window, near)


def plot(j, folder, out, window, near):
    recording = j["recording"]
    observer = [(float(r["t_s"]), float(r["lat_deg"]), float(r["lon_deg"])) for r in read_rows(os.path.join(folder, "observer.csv"))]
    truth = read_rows(os.path.join(folder, "truth.csv"))
    detections = [r for r in read_rows(os.path.join(folder, "detections.csv")) if r["range_m"] and r["bearing_deg"]]
    track = sorted({float(r["t_s"]): (float(r["lat_deg"]), float(r["lon_deg"]))
                    for r in truth if r["target"] == j["target"]}.items())
    if not track:
        die("%s: no reference of target %s" % (folder, j["target"]))
    t_jump = j["t_s"]
    lat0, lon0 = min(track, key=lambda x: abs(x[0] - t_jump))[1]
    cos0 = math.cos(math.radians(lat0))

    def ne(lat, lon):
        return (math.radians(lat - lat0) * EARTH_M, math.radians(lon - lon0) * EARTH_M * cos0)

    def interpolator(series):  # series: sorted (t, (a, b)) -> t -> (a, b) linear in t, None outside
        ts = numpy.array([x[0] for x in series])
        ab = numpy.array([x[1] for x in series]).reshape(-1, 2)

        def at(t):
            if not len(ts) or t < ts[0] or t > ts[-1]:
                return None
            return (float(numpy.interp(t, ts, ab[:, 0])), float(numpy.interp(t, ts, ab[:, 1])))
        return at

    inside = [(t, ne(*p)) for t, p in track if abs(t - t_jump) <= window]
    own = [(t, ne(la, lo)) for t, la, lo in observer]
    fig, (ax, sp) = plt.subplots(2, 1, figsize=(8, 10), gridspec_kw={"height_ratios": [3, 1]})
    used = [(t, p) for t, p in inside if j["used_from_s"] <= t <= j["used_to_s"]]
    cut = [(t, p) for t, p in inside if not j["used_from_s"] <= t <= j["used_to_s"]]
    if used:
        ax.plot([p[1] for _, p in used], [p[0] for _, p in used], "-", color="k", lw=1.5, label="reference, used")
    if cut:
        ax.plot([p[1] for _, p in cut], [p[0] for _, p in cut], "--", color="tab:red", lw=1.5, label="reference, not used")
    own_at, ref_at = interpolator(own), interpolator(inside)
    for sensor, marker in (("lidar", "o"), ("radar", "s")):
        pts = []
        for r in detections:
            if r["sensor"] != sensor:
                continue
            t = float(r["t_s"])
            if abs(t - t_jump) > window:
                continue
            o, p_ref = own_at(t), ref_at(t)
            if o is None or p_ref is None:
                continue
            b, rng = math.radians(float(r["bearing_deg"])), float(r["range_m"])
            p = (o[0] + rng * math.cos(b), o[1] + rng * math.sin(b))
            if math.hypot(p[0] - p_ref[0], p[1] - p_ref[1]) <= near:
                pts.append(p)
        if pts:
            ax.plot([p[1] for p in pts], [p[0] for p in pts], marker, ms=4, alpha=0.7, label="%s detections" % sensor)
    ax.plot([0], [0], "x", color="tab:red", ms=10, label="jump at %.1f s" % (t_jump - track[0][0]))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    title = "%s%s: reference %.2f m off its path (bound %.2f m)" % (
        recording + " " if recording else "", j["target"], j["deviation_m"], j["bound_m"])
    ax.set_title(title)
    ax.legend(fontsize=8)
    speeds = [((t1 + t0) / 2 - track[0][0], math.hypot(p1[0] - p0[0], p1[1] - p0[1]) / (t1 - t0))
              for (t0, p0), (t1, p1) in zip(inside, inside[1:]) if t1 > t0]
    sp.plot([s[0] for s in speeds], [s[1] for s in speeds], "-", color="k", lw=1)
    sp.axvline(t_jump - track[0][0], color="tab:red", ls=":")
    sp.set_xlabel("time after the reference's first sample [s]")
    sp.set_ylabel("reference speed [m/s]")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)
    print("plot_reference_jump: wrote %s" % out)


if __name__ == "__main__":
    main()
