#include "prl_error_model.hpp"

#include <cmath>

namespace rnav {

PolarGaussMarkov::PolarGaussMarkov(const PolarError& sigma, double tau_s, Part part)
    : d_(sigma.range_m, tau_s), e_(sigma.course_rad, tau_s), g_(sigma.glide_rad, tau_s), part_(part) {}

void PolarGaussMarkov::start(Rng& rng) {
  d_.start(rng);
  e_.start(rng);
  g_.start(rng);
  last_t_s_ = 0;
}

void PolarGaussMarkov::apply(const PlotTruth& truth, Rng& rng, PolarError& sys, PolarError& fl) {
  const double dt = truth.t_s - last_t_s_;
  last_t_s_ = truth.t_s;
  (part_ == Part::kSystematic ? sys : fl) += PolarError{d_.step(dt, rng), e_.step(dt, rng), g_.step(dt, rng)};
}

void WhiteFluctuation::apply(const PlotTruth&, Rng& rng, PolarError&, PolarError& fl) {
  fl += PolarError{s_.range_m * rng.normal(), s_.course_rad * rng.normal(),
                   s_.glide_rad * rng.normal()};
}

void Outliers::apply(const PlotTruth&, Rng& rng, PolarError&, PolarError& fl) {
  const bool hit = rng.uniform() < p_;
  const PolarError n{s_.range_m * rng.normal(), s_.course_rad * rng.normal(), s_.glide_rad * rng.normal()};
  if (hit) fl += n;
}

GeometricEffects::GeometricEffects(const PrlEffectsOptions& fx, double az_deg) : fx_(fx) {
  const double b = az_deg * kDegToRad;
  // R's axes in ENU (frames.hpp): x = (sin b, cos b, 0), y = up, z = (cos b, -sin b, 0)
  const Eigen::Vector3d enu(fx.site_offset_east_m, fx.site_offset_north_m, fx.site_offset_up_m);
  site_offset_R_ = {std::sin(b) * enu.x() + std::cos(b) * enu.y(), enu.z(),
                    std::cos(b) * enu.x() - std::sin(b) * enu.y()};
}

void GeometricEffects::apply(const PlotTruth& t, Rng&, PolarError& sys, PolarError&) {
  const Eigen::Matrix3d J = polar_jacobian(t.p_RA_R);
  const double D = t.polar.range_m, Eg = t.polar.glide_rad;
  // range_gain: dD = g D
  sys.range_m += fx_.range_gain * D;
  // time_offset: a plot stamped t was taken at t - tau: dzeta = -zeta_dot tau, zeta_dot = J v
  const Eigen::Vector3d rate = J * t.v_A_R;
  sys += PolarError{-rate[0] * fx_.time_offset_s, -rate[1] * fx_.time_offset_s,
                    -rate[2] * fx_.time_offset_s};
  // elevation_refraction: dEg = k cot(Eg)
  if (fx_.elevation_refraction_rad != 0) sys.glide_rad += fx_.elevation_refraction_rad / std::tan(Eg);
  // azimuth_elevation_coupling: dEk = c tan(Eg)
  sys.course_rad += fx_.azimuth_elevation_coupling_rad * std::tan(Eg);
  // site_offset: the radar measures from the true site = surveyed - delta, so
  // p_meas = p_RA + delta and dzeta = J delta (first order; delta << D)
  const Eigen::Vector3d ds = J * site_offset_R_;
  sys += PolarError{ds[0], ds[1], ds[2]};
  // bias_drift: dzeta = rate t
  sys += PolarError{fx_.drift_range_mps * t.t_s, fx_.drift_course_radps * t.t_s,
                    fx_.drift_glide_radps * t.t_s};
  // bias_step: dzeta = m 1[t >= t_step]
  if (fx_.step_time_s >= 0 && t.t_s >= fx_.step_time_s)
    sys += PolarError{fx_.step_range_m, fx_.step_course_rad, fx_.step_glide_rad};
  // periodic: dzeta = A sin(2 pi t / P)
  if (fx_.periodic_period_s > 0) {
    const double s = std::sin(2 * M_PI * t.t_s / fx_.periodic_period_s);
    sys += PolarError{fx_.periodic_range_m * s, fx_.periodic_course_rad * s, fx_.periodic_glide_rad * s};
  }
}

PrlErrorModel::PrlErrorModel(const PrlOptions& o, const PrlEffectsOptions& fx,
                             double azimuth_reference_deg) {
  effects_.push_back(std::make_unique<ConstantBias>(
      PolarError{o.bias_range_m, o.bias_course_deg * kDegToRad, o.bias_glide_deg * kDegToRad}));
  if (o.drift_sigma_range_m > 0 || o.drift_sigma_course_deg > 0 || o.drift_sigma_glide_deg > 0)
    effects_.push_back(std::make_unique<PolarGaussMarkov>(
        PolarError{o.drift_sigma_range_m, o.drift_sigma_course_deg * kDegToRad,
                   o.drift_sigma_glide_deg * kDegToRad},
        o.drift_tau_s, PolarGaussMarkov::Part::kSystematic));
  // Table 1 gives fluctuation errors as 2 sigma; noise_scale multiplies them.
  const PolarError sigma{o.noise2s_range_m / 2 * fx.noise_scale,
                         o.noise2s_course_deg / 2 * kDegToRad * fx.noise_scale,
                         o.noise2s_glide_deg / 2 * kDegToRad * fx.noise_scale};
  if (fx.correlated_noise_tau_s > 0)
    effects_.push_back(
        std::make_unique<PolarGaussMarkov>(sigma, fx.correlated_noise_tau_s, PolarGaussMarkov::Part::kFluctuation));
  else
    effects_.push_back(std::make_unique<WhiteFluctuation>(sigma));
  const bool geometric = fx.range_gain != 0 || fx.time_offset_s != 0 ||
                         fx.elevation_refraction_rad != 0 || fx.azimuth_elevation_coupling_rad != 0 ||
                         fx.site_offset_east_m != 0 || fx.site_offset_north_m != 0 ||
                         fx.site_offset_up_m != 0 || fx.drift_range_mps != 0 ||
                         fx.drift_course_radps != 0 || fx.drift_glide_radps != 0 ||
                         fx.step_time_s >= 0 || fx.periodic_period_s > 0;
  if (geometric) effects_.push_back(std::make_unique<GeometricEffects>(fx, azimuth_reference_deg));
  if (fx.outlier_prob > 0)
    effects_.push_back(std::make_unique<Outliers>(
        fx.outlier_prob, PolarError{sigma.range_m * fx.outlier_scale, sigma.course_rad * fx.outlier_scale,
                                    sigma.glide_rad * fx.outlier_scale}));
}

void PrlErrorModel::start(Rng& rng) {
  for (auto& e : effects_) e->start(rng);
}

void PrlErrorModel::apply(const PlotTruth& truth, Rng& rng, PolarError& systematic,
                          PolarError& total) {
  systematic = PolarError{};
  PolarError fluct;
  for (auto& e : effects_) e->apply(truth, rng, systematic, fluct);
  total = systematic;
  total += fluct;
}

}  // namespace rnav
