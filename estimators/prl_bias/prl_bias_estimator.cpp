#include "estimators/prl_bias/prl_bias_estimator.hpp"

#include <cmath>

namespace rnav {

namespace {
double sq(double x) { return x * x; }
}  // namespace

PrlBiasEstimator::PrlBiasEstimator(const PrlBiasOptions& o, std::int64_t epoch_utime)
    : o_(o),
      epoch_utime_(epoch_utime),
      switch_utime_(epoch_utime + to_us(o.switch_time_s)),
      r1_{sq(o.noise2s_range_m / 2), sq(o.noise2s_course_deg / 2 * kDegToRad),
          sq(o.noise2s_glide_deg / 2 * kDegToRad)},
      kf_{ScalarGmKalman(o.delta_range_m, o.tau_s),
          ScalarGmKalman(o.delta_course_deg * kDegToRad, o.tau_s),
          ScalarGmKalman(o.delta_glide_deg * kDegToRad, o.tau_s)} {}

void PrlBiasEstimator::reset() {
  for (auto& k : kf_) k.reset();
}

PrlBiasEstimator::Output PrlBiasEstimator::process(const prl_plot_t& plot,
                                                   const std::optional<NavAtPlot>& nav) {
  Output out;
  auto& e = out.estimate;
  e.utime = plot.utime;
  e.plot_id = plot.plot_id;
  e.has_chi = false;
  for (int i = 0; i < 3; ++i) e.chi[i] = e.gain[i] = 0;
  const double t_s = (plot.utime - epoch_utime_) * 1e-6;
  const bool estimating = plot.utime < switch_utime_;

  if (estimating && nav) {
    // zeta2: the nav solution in the radar's polar basis at the plot's time of validity
    const Polar z2 = polar_from_cartesian(nav->p_RA_R);
    // chi = zeta1_meas - zeta2 (5)
    const double chi[3] = {plot.range_m - z2.range_m, wrap_pi(plot.course_rad - z2.course_rad),
                           plot.glide_rad - z2.glide_rad};
    // r = r1 (+ p2: nav variance sigma^2 I projected by the polar Jacobian, diagonal)
    double p2[3] = {0, 0, 0};
    if (o_.add_nav_variance) {
      const Eigen::Matrix3d J = polar_jacobian(nav->p_RA_R);
      const Eigen::Matrix3d P = sq(nav->sigma_pos_m) * J * J.transpose();
      for (int i = 0; i < 3; ++i) p2[i] = P(i, i);
    }
    e.has_chi = true;
    for (int i = 0; i < 3; ++i) {
      e.chi[i] = chi[i];
      e.gain[i] = kf_[i].update(t_s, chi[i], r1_[i] + p2[i]);
    }
    e.mode = prl_bias_estimate_t::ESTIMATING;
  } else if (!kf_[0].initialized()) {
    e.mode = prl_bias_estimate_t::NO_ESTIMATE;
  } else {
    e.mode = estimating ? prl_bias_estimate_t::NAV_DROPOUT : prl_bias_estimate_t::COMPENSATING;
  }
  for (int i = 0; i < 3; ++i) {
    e.eta[i] = kf_[i].eta();
    e.var[i] = kf_[i].p();
  }

  // Compensation: zeta_comp = zeta_meas - eta_hat, after the switch and on drop-outs
  // (and during estimation if so configured); otherwise the plot passes through.
  out.compensated = plot;
  const bool compensate =
      kf_[0].initialized() && (e.mode != prl_bias_estimate_t::ESTIMATING || o_.compensate_during_estimation);
  if (compensate) {
    out.compensated.range_m = plot.range_m - e.eta[0];
    out.compensated.course_rad = wrap_pi(plot.course_rad - e.eta[1]);
    out.compensated.glide_rad = plot.glide_rad - e.eta[2];
  }
  return out;
}

}  // namespace rnav
