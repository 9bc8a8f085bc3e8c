#include "sim/uav/bearing_error_model.hpp"

#include "common/physics/bearing_effect_columns.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav {

double CorrelatedBearingNoise::error(const BearingTruth& truth, Rng& rng) {
  const double dt = started_ ? truth.t_s - t_prev_s_ : 0.0;
  if (dt < 0) throw std::logic_error("CorrelatedBearingNoise: frames out of time order");
  started_ = true;
  t_prev_s_ = truth.t_s;
  return dt > 0 ? gm_.step(dt, rng) : gm_.value();
}

// The catalogue's columns (common/physics/bearing_effect_columns.hpp) times this sensor's parameters.
double SystematicBearingError::error(const BearingTruth& truth, Rng&) {
  namespace fx = bearing_effect;
  const fx::FrameGeometry f{truth.t_s, truth.bearing_rate_radps};
  double e = fx::bias(f)(0) * o_.bearing_bias_rad + fx::time_offset(f)(0) * o_.time_offset_s +
             fx::bias_drift(f, 0.0)(0) * o_.bias_drift_radps;
  if (o_.periodic_period_s > 0) e += fx::periodic(f, o_.periodic_period_s).dot(Eigen::Vector2d(o_.periodic_amplitude_rad, 0));
  return e;
}

double BearingOutliers::error(const BearingTruth&, Rng& rng) {
  const double u = rng.uniform(), z = rng.normal();
  return u < p_ ? s_ * z : 0.0;
}

BearingErrorModel::BearingErrorModel(const SensorOptions& o, const SensorEffectsOptions& fx) {
  const double sigma = o.sigma_deg * kDegToRad * fx.noise_scale;
  if (fx.correlated_noise_tau_s > 0)
    effects_.push_back(std::make_unique<CorrelatedBearingNoise>(sigma, fx.correlated_noise_tau_s));
  else
    effects_.push_back(std::make_unique<WhiteBearingNoise>(sigma));
  if (fx.bearing_bias_rad != 0 || fx.time_offset_s != 0 || fx.bias_drift_radps != 0 ||
      (fx.periodic_period_s > 0 && fx.periodic_amplitude_rad != 0))
    effects_.push_back(std::make_unique<SystematicBearingError>(fx));
  if (fx.outlier_prob > 0) effects_.push_back(std::make_unique<BearingOutliers>(fx.outlier_prob, fx.outlier_scale * sigma));
}

void BearingErrorModel::start(Rng& rng) {
  for (auto& e : effects_) e->start(rng);
}

double BearingErrorModel::error(const BearingTruth& truth, Rng& rng) {
  double sum = 0;
  for (auto& e : effects_) sum += e->error(truth, rng);
  return sum;
}

}  // namespace rnav
