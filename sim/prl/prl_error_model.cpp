#include "sim/prl/prl_error_model.hpp"

#include "common/physics/prl_effect_columns.hpp"

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

GeometricEffects::GeometricEffects(const PrlEffectsOptions& fx, double az_deg)
    : fx_(fx), R_R_ENU_(prl_effect::R_R_ENU(az_deg)) {}

namespace {
void add(PolarError& e, const Eigen::Vector3d& d) { e += PolarError{d[0], d[1], d[2]}; }
}  // namespace

// d zeta = sum over the catalogue's deterministic entries of C(plot) theta, with the columns the
// diagnosis fits (prl_effect_columns.hpp); an entry whose parameters are 0 adds nothing.
void GeometricEffects::apply(const PlotTruth& t, Rng&, PolarError& sys, PolarError&) {
  namespace fx = prl_effect;
  fx::PlotGeometry g;
  g.t_s = t.t_s;
  g.range_m = t.polar.range_m;
  g.glide_rad = t.polar.glide_rad;
  g.J = polar_jacobian(t.p_RA_R);
  g.rate = g.J * t.v_A_R;
  if (fx_.range_gain != 0) add(sys, fx::range_gain(g) * fx_.range_gain);
  if (fx_.time_offset_s != 0) add(sys, fx::time_offset(g) * fx_.time_offset_s);
  if (fx_.elevation_refraction_rad != 0) add(sys, fx::elevation_refraction(g) * fx_.elevation_refraction_rad);
  if (fx_.azimuth_elevation_coupling_rad != 0)
    add(sys, fx::azimuth_elevation_coupling(g) * fx_.azimuth_elevation_coupling_rad);
  const Eigen::Vector3d site_enu(fx_.site_offset_east_m, fx_.site_offset_north_m, fx_.site_offset_up_m);
  if (site_enu != Eigen::Vector3d::Zero()) add(sys, fx::site_offset(g, R_R_ENU_) * site_enu);
  const double drift[fx::kChannels] = {fx_.drift_range_mps, fx_.drift_course_radps, fx_.drift_glide_radps};
  const double step[fx::kChannels] = {fx_.step_range_m, fx_.step_course_rad, fx_.step_glide_rad};
  const double periodic[fx::kChannels] = {fx_.periodic_range_m, fx_.periodic_course_rad, fx_.periodic_glide_rad};
  for (int c = 0; c < fx::kChannels; ++c) {
    if (drift[c] != 0) add(sys, fx::bias_drift(g, c, 0.0) * drift[c]);
    if (fx_.step_time_s >= 0 && step[c] != 0) add(sys, fx::bias_step(g, c, fx_.step_time_s) * step[c]);
    // the simulator's oscillation has phase 0: (a_sin, a_cos) = (A, 0)
    if (fx_.periodic_period_s > 0 && periodic[c] != 0)
      add(sys, fx::periodic(g, c, fx_.periodic_period_s) * Eigen::Vector2d(periodic[c], 0));
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
