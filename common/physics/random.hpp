// Reproducible random streams and the first-order Gauss-Markov process.
#pragma once

#include <cstdint>
#include <random>

namespace rnav {

/// Stream identifiers: each node draws from its own stream so that one node's draws never
/// shift another's (determinism whatever the scheduling).
enum class Stream : std::uint64_t { kSnsins = 1, kPrl = 2, kTrajectory = 3, kUav = 4, kTmaParticle = 5, kDatalink = 6, kTest = 99 };

/// A random stream determined by (ensemble seed, realization, stream) only.
/// Uses std::mt19937_64 (fully specified by the C++ standard) and libstdc++'s normal
/// distribution: outputs are byte-identical for the same build and library.
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t realization, Stream stream);
  /// Standard normal N(0, 1).
  double normal() { return normal_(engine_); }
  /// Uniform in [0, 1).
  double uniform() { return uniform_(engine_); }

 private:
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

/// First-order Gauss-Markov process with autocorrelation K(tau) = sigma^2 exp(-|tau|/T),
///   d eta/dt = -eta/T + sqrt(2/T) sigma xi(t),
/// sampled exactly: eta(k+1) = phi eta(k) + w(k), phi = exp(-dt/T), Var w = sigma^2 (1 - phi^2).
/// T = infinity gives a random constant; sigma = 0 gives zero.
class GaussMarkov {
 public:
  /// @param sigma  stationary standard deviation [unit of the process], >= 0
  /// @param tau_s  correlation time T [s], > 0 (infinity allowed)
  GaussMarkov(double sigma, double tau_s);
  /// Draw the initial value from the stationary distribution N(0, sigma^2).
  void start(Rng& rng);
  /// Advance by dt_s >= 0 seconds and return the new value.
  double step(double dt_s, Rng& rng);
  double value() const { return x_; }
  double sigma() const { return sigma_; }
  double tau_s() const { return tau_s_; }

 private:
  double sigma_, tau_s_, x_ = 0;
};

}  // namespace rnav
