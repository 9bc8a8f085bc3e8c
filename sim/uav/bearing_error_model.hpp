// The passive sensor's bearing error: a list of effects, each adding to the measured bearing
//   bearing_meas = bearing_true + sum(effects)
// The diagnosis catalogue's effects (SensorEffectsOptions, all off by default) are added only
// when enabled, so a nominal run draws exactly the random numbers it always drew. Further
// effects: derive from BearingErrorEffect and add them in BearingErrorModel's constructor.
#pragma once

#include "common/physics/random.hpp"
#include "common/physics/frames.hpp"
#include "sim/uav/sensor_options.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rnav {

/// What an effect may depend on: the frame's time and the true geometry.
struct BearingTruth {
  double t_s = 0;          ///< [s] time of validity
  double bearing_rad = 0;  ///< [rad] true bearing, clockwise from north
  double range_m = 0;      ///< [m] true horizontal range
  double bearing_rate_radps = 0;  ///< [rad/s] true bearing rate
};

class BearingErrorEffect {
 public:
  virtual ~BearingErrorEffect() = default;
  virtual std::string name() const = 0;
  virtual void start(Rng&) {}
  /// The effect's error [rad] for one frame (called for every frame, detected or not, so the
  /// random stream does not depend on the field of regard).
  virtual double error(const BearingTruth& truth, Rng& rng) = 0;
};

/// White noise, sigma_deg (1 sigma).
class WhiteBearingNoise : public BearingErrorEffect {
 public:
  explicit WhiteBearingNoise(double sigma_rad) : s_(sigma_rad) {}
  std::string name() const override { return "white_noise"; }
  double error(const BearingTruth&, Rng& rng) override { return s_ * rng.normal(); }

 private:
  double s_;
};

/// Gauss-Markov noise (correlated_noise): sigma, correlation time tau_s; advanced by the time
/// since the previous frame.
class CorrelatedBearingNoise : public BearingErrorEffect {
 public:
  CorrelatedBearingNoise(double sigma_rad, double tau_s) : gm_(sigma_rad, tau_s) {}
  std::string name() const override { return "correlated_noise"; }
  void start(Rng& rng) override {
    gm_.start(rng);
    started_ = false;
  }
  double error(const BearingTruth& truth, Rng& rng) override;

 private:
  GaussMarkov gm_;
  double t_prev_s_ = 0;
  bool started_ = false;
};

/// Deterministic errors: bearing_bias b, bearing_time_offset tau, bias_drift d, periodic (P, A):
///   e = b - beta_dot tau + d t + A sin(2 pi t / P)
/// (a stamp late by tau shows the bearing of t - tau: beta(t - tau) - beta(t) = -beta_dot tau).
class SystematicBearingError : public BearingErrorEffect {
 public:
  explicit SystematicBearingError(const SensorEffectsOptions& o) : o_(o) {}
  std::string name() const override { return "systematic"; }
  double error(const BearingTruth& truth, Rng&) override;

 private:
  SensorEffectsOptions o_;
};

/// Outliers: with probability p per frame, an extra N(0, (scale sigma)^2) error. Draws two
/// numbers every frame, so whether a frame is an outlier does not shift the stream.
class BearingOutliers : public BearingErrorEffect {
 public:
  BearingOutliers(double prob, double sigma_rad) : p_(prob), s_(sigma_rad) {}
  std::string name() const override { return "outliers"; }
  double error(const BearingTruth&, Rng& rng) override;

 private:
  double p_, s_;
};

class BearingErrorModel {
 public:
  BearingErrorModel(const SensorOptions& o, const SensorEffectsOptions& fx = {});
  void start(Rng& rng);
  /// Total error [rad] of one frame.
  double error(const BearingTruth& truth, Rng& rng);

 private:
  std::vector<std::unique_ptr<BearingErrorEffect>> effects_;
};

}  // namespace rnav
