// The passive sensor's bearing error: a list of effects, each adding to the measured bearing
//   bearing_meas = bearing_true + sum(effects)
// Open for further effects (a bearing bias, a time-stamp latency, ...): derive from
// BearingErrorEffect and add it in BearingErrorModel's constructor.
#pragma once

#include "random.hpp"
#include "uav_scenario.hpp"

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

class BearingErrorModel {
 public:
  explicit BearingErrorModel(const SensorOptions& o);
  void start(Rng& rng);
  /// Total error [rad] of one frame.
  double error(const BearingTruth& truth, Rng& rng);

 private:
  std::vector<std::unique_ptr<BearingErrorEffect>> effects_;
};

}  // namespace rnav
