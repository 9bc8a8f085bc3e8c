#!/usr/bin/python3
"""Markdown tables of scene validations (rnav_scene validate --json: recorded scenes or landing
flights) and a closure (rnav_scene closure --json): per recording, the pairs with >= min_n detections inside the simulations' 5-95 %
band on every statistic, nominal and extended; per statistic, the share of rows inside; the
closure's naming rate and mean estimate per injected effect.

usage: scene_validation_table.py VALIDATION.json... [--closure CLOSURE.json]
"""
import argparse
import json
import re
from collections import defaultdict

# the statistics in the order shown (a landing flight's pair has range, azimuth and elevation)
STATS = [(q, s) for q in ("bearing", "range", "azimuth", "elevation") for s in ("mean", "sd", "lag1")] + [("detection", "detection_rate")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("validations", nargs="+")
    ap.add_argument("--closure")
    a = ap.parse_args()
    per_stat = defaultdict(lambda: [0, 0])
    total = defaultdict(lambda: [0, 0])
    print("| recording | pairs (n >= min) | nominal: all inside | extended: all inside | extended: pairs still outside (statistics) |")
    print("|---|---|---|---|---|")
    loaded = []
    for f in a.validations:
        with open(f) as fh:
            loaded.append(json.load(fh))
    # recordings in natural order (sc2 before sc13)
    loaded.sort(key=lambda v: [int(x) if x.isdigit() else x for x in re.split(r"(\d+)", v["recording"])])
    for v in loaded:
        pairs = defaultdict(dict)
        for r in v["rows"]:
            if r["n"] < v["min_n"]:
                continue
            pairs[(r["pair"], r["model"])][(r["quantity"], r["statistic"])] = r["inside"]
            s = per_stat[(r["model"], r["quantity"], r["statistic"])]
            s[0] += r["inside"]
            s[1] += 1
        cells, outside = {}, []
        for m in ("nominal", "extended"):
            ps = {p: d for (p, mm), d in pairs.items() if mm == m}
            k = sum(all(d.values()) for d in ps.values())
            cells[m] = "%d of %d" % (k, len(ps))
            total[m][0] += k
            total[m][1] += len(ps)
            if m == "extended":
                for p, d in sorted(ps.items()):
                    bad = ["detection rate" if s == "detection_rate" else q + " " + s for (q, s), ok in d.items() if not ok]
                    if bad:
                        outside.append("%s (%s)" % (p, ", ".join(bad)))
        n_pairs = len({p for (p, _) in pairs})
        print("| %s | %d | %s | %s | %s |" % (v["recording"], n_pairs, cells.get("nominal", "-"), cells.get("extended", "-"),
                                            "; ".join(outside) or "none"))
    print()
    for m in ("nominal", "extended"):
        k, n = total[m]
        if n:
            print("%s: %d of %d pairs (%.0f %%) inside on every statistic" % (m, k, n, 100.0 * k / n))
    print()
    print("| statistic | nominal: rows inside | extended: rows inside |")
    print("|---|---|---|")
    for q, s in STATS:
        if not any(per_stat[(m, q, s)][1] for m in ("nominal", "extended")):
            continue  # a statistic none of the recordings has
        cells = []
        for m in ("nominal", "extended"):
            k, n = per_stat[(m, q, s)]
            cells.append("%d of %d (%.0f %%)" % (k, n, 100.0 * k / n) if n else "-")
        print("| %s | %s | %s |" % ("detection rate" if s == "detection_rate" else q + " " + s, cells[0], cells[1]))
    if a.closure:
        with open(a.closure) as fh:
            c = json.load(fh)
        print()
        print("Closure on %s: %d simulations with its diagnosis's effects, each diagnosed" % (c["recording"], c["runs"]))
        print()
        print("| effect | scope | named | injected | mean of the named (sd) | within 2 SE |")
        print("|---|---|---|---|---|---|")
        for e in c["effects"]:
            scope = "%s:%s" % (e["sensor"] or "-", e["target"] or "-")
            inj = ", ".join("%.4g" % x for x in e["injected"])
            mean = ", ".join("-" if m is None else "%.4g (%.2g)" % (m, s or 0) for m, s in zip(e["mean"], e["sd"]))
            print("| %s | %s | %d of %d | %s | %s | %s |" % (e["name"], scope, e["named"], e["runs"], inj, mean,
                                                           ", ".join("yes" if w else "no" for w in e["within_2se"])))


if __name__ == "__main__":
    main()
