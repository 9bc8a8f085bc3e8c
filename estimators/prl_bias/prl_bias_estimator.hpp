// The radar systematic-error estimator (docs/method.md section 1), one plot at a time, no I/O:
//   nav solution at the plot's time -> radar polar coordinates zeta2
//   chi = zeta1_meas - zeta2   (course difference wrapped)                          (5), (6)
//   one ScalarGmKalman per coordinate (range, course, glide)                         (11)
//   before switch_time_s: estimate (plots pass through unless compensate_during_estimation);
//   after it, and on nav drop-outs: compensate with the last estimate, zeta_comp = zeta_meas - eta_hat.
#pragma once

#include "estimators/prl_bias/nav_interpolator.hpp"
#include "estimators/prl_bias/scalar_gm_kalman.hpp"
#include "estimators/prl_bias/prl_bias_options.hpp"
#include "common/physics/sim_time.hpp"

#include <rnav/prl_bias_estimate_t.hpp>
#include <rnav/prl_plot_t.hpp>

#include <array>
#include <optional>

namespace rnav {

/// Navigation position at a plot's time, in R, with its per-axis 1 sigma.
struct NavAtPlot {
  Eigen::Vector3d p_RA_R;
  double sigma_pos_m = 0;
};

class PrlBiasEstimator {
 public:
  PrlBiasEstimator(const PrlBiasOptions& o, std::int64_t epoch_utime);
  void reset();

  struct Output {
    prl_bias_estimate_t estimate;
    prl_plot_t compensated;
  };
  /// Process one plot (plots in increasing time). `nav` is empty on a nav drop-out.
  Output process(const prl_plot_t& plot, const std::optional<NavAtPlot>& nav);

  /// The radar noise variance r1 per coordinate [m^2, rad^2, rad^2] (Table 1: 2 sigma given).
  const std::array<double, 3>& r1() const { return r1_; }
  bool estimating_at(std::int64_t utime) const { return utime < switch_utime_; }

 private:
  PrlBiasOptions o_;
  std::int64_t epoch_utime_, switch_utime_;
  std::array<double, 3> r1_;
  std::array<ScalarGmKalman, 3> kf_;
};

}  // namespace rnav
