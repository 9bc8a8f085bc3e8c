#!/usr/bin/env python3
"""ctest python.plot_gaps: diagnosis plot lines break at data gaps and nowhere else
(scripts/plot_gaps.py). Usage: PYTHONPATH=SOURCE_DIR/scripts check_plot_gaps.py (ctest sets it)"""
import math
import sys

import plot_gaps

fails = []
# 1 Hz with jitter of +-0.2 s, one 5 s gap after t = 10 (a dropped sensor) and a 2.5 s step
# after t = 20 (within 3x the median: not a gap).
t = [i + (0.2 if i % 2 else -0.2) for i in range(11)] + [15 + i for i in range(6)] + [22.5 + i for i in range(5)]
y = [float(i) for i in range(len(t))]
g = plot_gaps.gaps(t)
if g != [11]:
    fails.append("gaps at %s, expected [11] (the step from %.1f to %.1f)" % (g, t[10], t[11]))
bt, by = plot_gaps.broken(t, y)
nans = [i for i, v in enumerate(by) if math.isnan(v)]
if len(bt) != len(t) + 1 or nans != [11] or not t[10] < bt[11] < t[11]:
    fails.append("broken(): NaN at %s of %d points, expected one at 11 between %.1f and %.1f" % (nans, len(bt), t[10], t[11]))
if [v for v in by if not math.isnan(v)] != y:
    fails.append("broken() changed the data points")
if plot_gaps.gaps([0.0, 1.0, 2.0, 3.0]) or plot_gaps.gaps([5.0]) or plot_gaps.gaps([]):
    fails.append("gaps found in an evenly sampled or too short series")
for f in fails:
    print("FAIL: " + f)
print("%d failure(s)" % len(fails))
sys.exit(1 if fails else 0)
