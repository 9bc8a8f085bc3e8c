#!/usr/bin/python3
"""The pooled Autoferry tables of docs/autoferry-multi-sensor.md from one `rnav_diagnose multi
DIR1 ... DIR9 --json` report (scripts/autoferry_study --pooled writes it): the hardware effects
(one value in every recording) with their per-recording spread, each recording's own effects,
the scope answers, and the leave-one-recording-out error per sensor:target pair with its summary
(pairs with >= 5 detections)."""
import json
import math
import re

from rnav import cli_args
from rnav.effect_labels import scope_text

MEAN_EFFECTS_SKIPPED = ("noise_scale", "correlated_noise", "outliers", "target_maneuver")
MIN_N = 5          # detections a pair needs to count in the summary (the rule)
SAME = 0.03        # |ratio - 1| within this: unchanged
WORSE_LIMIT = 1.10  # the acceptance bound on any pair's ratio

ap = cli_args.ArgumentParser("autoferry_pooled_table.py", __doc__)
ap.add_argument("report", metavar="REPORT.json", nargs="?", help="the JSON report of a pooled multi diagnosis (required)")
args = ap.parse_args()
if args.report is None:
    ap.error("REPORT.json is required (see autoferry_pooled_table.py --help)")
try:
    rep = json.load(open(args.report))
    rep["leave_one_out"], rep["effects"], rep["scope_support"]
except (OSError, ValueError, KeyError) as e:
    ap.error("%s is not a pooled multi-diagnosis report (%s)" % (args.report, e))
DEG = 180 / math.pi


def shown(name, value):
    """A parameter as the text report shows it: radians in degrees."""
    return (value * DEG, name[:-4] + "_deg" if name.endswith("_rad") else "deg") if name in ("rad",) or name.endswith("_rad") \
        else (value, name)


def fmt(e, values, errors):
    out = []
    for p, v, s in zip(e["params"], values, errors):
        (v2, n), (s2, _) = shown(p, v), shown(p, s)
        out.append("%s %.3g ± %.2g" % ("ratio" if n == "1" else n, v2, s2))
    return ", ".join(out)


def listify(x):
    return x if isinstance(x, list) else [x]


def label(s):
    core = ":".join(x for x in (s.get("sensor"), s.get("target")) if x) or "common"
    return core


def rec_key(name):
    m = re.search(r"(\d+)$", name)
    return (int(m.group(1)) if m else 0, name)


mean = [e for e in rep["effects"] if e["name"] not in MEAN_EFFECTS_SKIPPED]
hardware = [e for e in mean if not e["scope"].get("recording")]
own = [e for e in mean if e["scope"].get("recording")]

print("Hardware (one value in every recording):\n")
print("| effect | on | pooled fit | per recording: random-effects mean (between-recording sd) | recordings |")
print("|---|---|---|---|---|")
for e in hardware:
    r = e.get("replication")
    rep_cell = "–"
    if r:
        rep_cell = "; ".join("%s (sd %.2g)" % (fmt(dict(e, params=[p]), [m], [s]), shown(p, sd)[0])
                             for p, m, s, sd in zip(e["params"], r["mean"], r["mean_se"], r["between_sd"]))
    scan = " at %s %.4g" % (e["scanned"]["param"], e["scanned"]["value"]) if "scanned" in e else ""
    print("| %s | %s | %s%s | %s | %s |" % (e["name"], label(e["scope"]), fmt(e, listify(e["estimate"]), listify(e["stderr"])), scan,
                                         rep_cell, len(r["recordings"]) if r else "–"))
if not hardware:
    print("| – | | | | |")

print("\nOne recording's own:\n")
print("| recording | effect | on | estimate |")
print("|---|---|---|---|")
for e in sorted(own, key=lambda e: rec_key(e["scope"]["recording"])):
    scan = " at %s %.1f" % (e["scanned"]["param"], e["scanned"]["value"]) if "scanned" in e else ""
    print("| %s | %s | %s | %s%s |" % (e["scope"]["recording"], e["name"], label(e["scope"]),
                                      fmt(e, listify(e["estimate"]), listify(e["stderr"])), scan))
if not own:
    print("| – | | | |")

carry = rep.get("carry")
if carry and carry["effects"]:
    if carry["tolerance"] > 0:
        print("\nCarried to a new recording (the hardware of the fit at alpha = %g, a prediction: the causes above are "
              "named at the report's alpha; each hardware value's share, on a grid of tenths, that gives the lowest error on "
              "these recordings while no pair of theirs gets worse than %g x its error with its recording's own effects "
              "removed; geometric mean there %.3f, with every value whole %.3f, worst %.2f (%s)):\n"
              % (carry["alpha"], carry["tolerance"], carry["fitted_recordings"]["chosen"]["geomean_ratio"],
                 carry["fitted_recordings"]["whole"]["geomean_ratio"], carry["fitted_recordings"]["whole"]["worst_ratio"],
                 carry["fitted_recordings"]["whole"]["worst"]))
    else:
        print("\nCarried to a new recording (the hardware of the fit at alpha = %g, every value whole: --carry-tolerance 0):\n"
              % carry["alpha"])
    print("| effect | on | share | carried |")
    print("|---|---|---|---|")
    for c in carry["effects"]:
        fitted = next((e for e in hardware if e["name"] == c["name"] and label(e["scope"]) == label(c["scope"])), None)
        # not named (the carried fit is at its own level): its parameters from the catalogue's limits
        limits = rep.get("detection_limits", {}).get("%s@%s" % (c["name"], scope_text(c) or "common"), {})
        params = fitted["params"] if fitted else list(limits) if len(limits) == len(c["estimate"]) else ["value"] * len(c["estimate"])
        cells = ", ".join("%s %.3g" % (("ratio" if shown(p, v)[1] == "1" else shown(p, v)[1]), shown(p, v)[0])
                          for p, v in zip(params, c["estimate"]))
        print("| %s | %s | %.1f | %s |" % (c["name"], label(c["scope"]), c["share"], cells if c["share"] > 0 else "not carried"))

print("\nScope answers:\n")
for q in rep["scope_support"]:
    print("- %s → **%s**" % (q["question"], q["supported"]))

print("\nLeave one recording out (fitted on the other eight, hardware carried as above, its shares chosen on those eight, "
      "scored on all of the left-out recording's detections; radar, lidar: position error [m]; eo, ir: bearing error [deg]):\n")
rows = {}
for x in rep["leave_one_out"]:
    rows.setdefault(x["recording"], []).append(x)
print("| recording | carried | nominal → extended |")
print("|---|---|---|")
for rec in sorted(rows, key=rec_key):
    cells = ", ".join("%s %.2f→%.2f" % (x["pair"], x["nominal_rms"], x["extended_rms"]) for x in rows[rec] if x["n"] >= MIN_N)
    carried = ", ".join(rep["leave_one_out_carried"].get(rec, [])) or "nothing that applies"
    print("| %s | %s | %s |" % (rec, carried, cells))
ratios = [(x["extended_rms"] / x["nominal_rms"], "%s %s" % (x["recording"], x["pair"]))
          for x in rep["leave_one_out"] if x["n"] >= MIN_N and x["nominal_rms"] > 0]
if ratios:
    lower = sum(r < 1 - SAME for r, _ in ratios)
    higher = sum(r > 1 + SAME for r, _ in ratios)
    beyond = sorted(((r, k) for r, k in ratios if r > WORSE_LIMIT), reverse=True)
    geo = math.exp(sum(math.log(r) for r, _ in ratios) / len(ratios))
    print("\n%d pairs with >= %d detections: %d lower by > 3 %%, %d higher by > 3 %%, %d within 3 %%; "
          "extended / nominal geometric mean %.3f, worst %.2f (%s); worse than %.2fx: %s"
          % (len(ratios), MIN_N, lower, higher, len(ratios) - lower - higher, geo, max(ratios)[0], max(ratios)[1], WORSE_LIMIT,
             ", ".join("%s %.3f" % (k, r) for r, k in beyond) or "none"))
