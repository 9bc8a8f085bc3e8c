#include "prl_error_model.hpp"

namespace rnav {

GaussMarkovDrift::GaussMarkovDrift(const PolarError& sigma, double tau_s)
    : d_(sigma.range_m, tau_s), e_(sigma.course_rad, tau_s), g_(sigma.glide_rad, tau_s) {}

void GaussMarkovDrift::start(Rng& rng) {
  d_.start(rng);
  e_.start(rng);
  g_.start(rng);
  last_t_s_ = 0;
}

void GaussMarkovDrift::apply(const PlotTruth& truth, Rng& rng, PolarError& sys, PolarError&) {
  const double dt = truth.t_s - last_t_s_;
  last_t_s_ = truth.t_s;
  sys += PolarError{d_.step(dt, rng), e_.step(dt, rng), g_.step(dt, rng)};
}

void WhiteFluctuation::apply(const PlotTruth&, Rng& rng, PolarError&, PolarError& fl) {
  fl += PolarError{s_.range_m * rng.normal(), s_.course_rad * rng.normal(),
                   s_.glide_rad * rng.normal()};
}

PrlErrorModel::PrlErrorModel(const PrlOptions& o) {
  effects_.push_back(std::make_unique<ConstantBias>(
      PolarError{o.bias_range_m, o.bias_course_deg * kDegToRad, o.bias_glide_deg * kDegToRad}));
  if (o.drift_sigma_range_m > 0 || o.drift_sigma_course_deg > 0 || o.drift_sigma_glide_deg > 0)
    effects_.push_back(std::make_unique<GaussMarkovDrift>(
        PolarError{o.drift_sigma_range_m, o.drift_sigma_course_deg * kDegToRad,
                   o.drift_sigma_glide_deg * kDegToRad},
        o.drift_tau_s));
  // Table 1 gives fluctuation errors as 2 sigma.
  effects_.push_back(std::make_unique<WhiteFluctuation>(
      PolarError{o.noise2s_range_m / 2, o.noise2s_course_deg / 2 * kDegToRad,
                 o.noise2s_glide_deg / 2 * kDegToRad}));
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
