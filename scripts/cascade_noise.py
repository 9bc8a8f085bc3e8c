"""Coloured noise the diagnosis does not model, for the study scripts (false_alarm_study).

White driving noise on a 0.01 s grid through two cascaded first-order low-pass filters of time
constant tau / 2 each: a second-order spectrum, autocorrelation (1 + 2|t|/tau) exp(-2|t|/tau),
not first-order Gauss-Markov, so a diagnosis whose noise family is Gauss-Markov does not share
the generator's assumptions. Started stationary (20 tau of warm-up before the first sample) and
scaled to unit variance by the exact stationary variance of the discrete cascade:
  f1 <- a f1 + sqrt(1 - a^2) w,  f2 <- a f2 + (1 - a) f1,  var f2 = (1 + a^2) / (1 + a)^2.
Python's own random module (Mersenne Twister, seeded): independent of the C++ simulator.
"""
import csv
import math
import random

STEP_S = 0.01


class Cascade:
    def __init__(self, tau_s, rng):
        if not tau_s > 0:
            raise ValueError("cascade noise: tau_s must be > 0, got %r" % tau_s)
        self.a = math.exp(-STEP_S / (tau_s / 2))
        self.b = math.sqrt(1 - self.a * self.a)
        self.norm = math.sqrt((1 + self.a ** 2) / (1 + self.a) ** 2)
        self.tau, self.rng = tau_s, rng
        self.t = None
        self.f1 = self.f2 = 0.0

    def at(self, t):
        """Unit-variance sample at time t [s] (times non-decreasing)."""
        if self.t is None:
            self.t = t - 20 * self.tau
        a, b, gauss = self.a, self.b, self.rng.gauss
        while self.t < t:
            self.f1 = a * self.f1 + b * gauss(0.0, 1.0)
            self.f2 = a * self.f2 + (1 - a) * self.f1
            self.t += STEP_S
        return self.f2 / self.norm


def add_to_radar_csv(path, tau_s, sigmas, seed):
    """Add cascade noise of 1-sigma `sigmas` = (range_m, azimuth_deg, elevation_deg) to a
    flight's radar.csv (t_s,range_m,azimuth_deg,elevation_deg), in place."""
    rng = random.Random(seed)
    gens = [Cascade(tau_s, rng) for _ in sigmas]
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if rows[0][:4] != ["t_s", "range_m", "azimuth_deg", "elevation_deg"]:
        raise ValueError("%s: unexpected header %r" % (path, rows[0]))
    out = [rows[0]]
    for line, r in enumerate(rows[1:], start=2):
        try:
            t = float(r[0])
            vals = [float(x) for x in r[1:4]]
        except (ValueError, IndexError):
            raise ValueError("%s:%d: malformed radar row %r" % (path, line, r))
        noisy = [v + s * g.at(t) for v, s, g in zip(vals, sigmas, gens)]
        out.append([r[0], "%.4f" % noisy[0], "%.8f" % noisy[1], "%.8f" % noisy[2]] + r[4:])
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(out)
