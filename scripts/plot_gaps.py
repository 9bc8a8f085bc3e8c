"""Lines that do not bridge data gaps: a line drawn across a gap in the samples suggests data
that are not there (a dropped sensor, an interrupted recording).

Rule: a gap is a step in time longer than GAP_FACTOR times the median step of the series; the
line is broken there by inserting a NaN (matplotlib does not draw across NaN).
"""
import math

GAP_FACTOR = 3.0  # a step over 3x the median sampling step is a gap


def gaps(t, factor=GAP_FACTOR):
    """Indices i where the step t[i] - t[i-1] is a gap (t increasing)."""
    steps = sorted(b - a for a, b in zip(t, t[1:]))
    if not steps:
        return []
    median = steps[len(steps) // 2] if len(steps) % 2 else 0.5 * (steps[len(steps) // 2 - 1] + steps[len(steps) // 2])
    return [i for i in range(1, len(t)) if t[i] - t[i - 1] > factor * median]


def broken(t, y, factor=GAP_FACTOR):
    """(t, y) with a NaN point inserted before every gap, for ax.plot(..., '-')."""
    cut = set(gaps(t, factor))
    bt, by = [], []
    for i, (a, b) in enumerate(zip(t, y)):
        if i in cut:
            bt.append(0.5 * (t[i - 1] + a))
            by.append(math.nan)
        bt.append(a)
        by.append(b)
    return bt, by
