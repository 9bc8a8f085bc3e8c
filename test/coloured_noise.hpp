// Test helper: coloured noise that is NOT first-order Gauss-Markov, so a diagnosis whose noise
// model is Gauss-Markov does not share the generator's assumptions.
#pragma once

#include <cmath>
#include <random>

namespace rnav::test {

// Coloured noise that is NOT first-order Gauss-Markov: white driving noise on a 0.01 s grid
// through two cascaded first-order low-pass filters of time constant tau / 2 each (a second-
// order spectrum; autocorrelation (1 + 2|t|/tau) exp(-2|t|/tau)), scaled to unit variance.
struct CascadeNoise {
  double tau, f1 = 0, f2 = 0, t = 0, a, norm;
  bool started = false;
  explicit CascadeNoise(double tau_s) : tau(tau_s), a(std::exp(-0.01 / (tau_s / 2))) {
    // The stationary variance of f2 for unit-variance f1 (AR(1) with coefficient a) through
    // f2 <- a f2 + (1 - a) f1 is (1 - a)^2 (1 + a^2) / (1 - a^2)^2 = (1 + a^2) / (1 + a)^2
    // (scripts/cascade_noise.py divides by it). Here the caller sets norm from a simulation
    // instead (cascade_norm, within 1.3 % of it for tau 0.5-30 s): the tests' seeded inputs were made so.
    norm = 1;
  }
  double at(double tt, std::mt19937_64& rng) {
    std::normal_distribution<double> N(0, 1);
    if (!started) t = tt - 20 * tau, started = true;  // stationary by the first sample
    while (t < tt) {
      f1 = a * f1 + std::sqrt(1 - a * a) * N(rng);
      f2 = a * f2 + (1 - a) * f1;
      t += 0.01;
    }
    return f2 / norm;
  }
};
inline double cascade_norm(double tau) {
  std::mt19937_64 rng(99);
  CascadeNoise c(tau);
  double s = 0;
  int n = 0;
  for (double t = 10 * tau; t < 4000 * tau; t += tau / 2, ++n) s += std::pow(c.at(t, rng), 2);
  return std::sqrt(s / n);
}

}  // namespace rnav::test
