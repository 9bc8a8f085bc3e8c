// The azimuth-only sensor's deterministic catalogue effects, written once: each effect's
// contribution to one frame's bearing error e [rad] is
//   d e = c(frame) theta,
// c a row of the frame's time and true bearing rate and theta the effect's parameters. The
// simulator injects c theta (sim/uav/bearing_error_model.cpp, SystematicBearingError) and the
// diagnosis fits theta on the same c (estimators/diagnosis/uav_diagnose.cpp), so what one can
// hide the other can name. The stochastic entries (noise_scale, correlated_noise, outliers) are
// noise models, not columns; target_maneuver moves the target, not the sensor, and is the
// diagnosis's own.
#pragma once

#include <Eigen/Dense>

#include <cmath>

namespace rnav::bearing_effect {

/// What the columns need of one frame.
struct FrameGeometry {
  double t_s = 0;                 ///< [s] time of validity, sim time since the run's start
  double bearing_rate_radps = 0;  ///< [rad/s] d beta / dt of the true bearing
};

/// bearing_bias, theta = b [rad]: de = b.
inline Eigen::RowVectorXd bias(const FrameGeometry&) { return Eigen::RowVectorXd::Ones(1); }

/// time_offset, theta = tau [s] (sensor stamp minus true time): a frame stamped t shows the
/// bearing of t - tau, so de = beta(t - tau) - beta(t) = -beta_dot tau (first order).
inline Eigen::RowVectorXd time_offset(const FrameGeometry& f) {
  return Eigen::RowVectorXd::Constant(1, -f.bearing_rate_radps);
}

/// bias_drift, theta = d [rad/s]: de = d (t - t0_s).
inline Eigen::RowVectorXd bias_drift(const FrameGeometry& f, double t0_s) {
  return Eigen::RowVectorXd::Constant(1, f.t_s - t0_s);
}

/// periodic of period_s [s] > 0, theta = (a_sin, a_cos) [rad]:
/// de = a_sin sin(2 pi t / P) + a_cos cos(2 pi t / P).
inline Eigen::RowVectorXd periodic(const FrameGeometry& f, double period_s) {
  Eigen::RowVectorXd r(2);
  r << std::sin(2 * M_PI * f.t_s / period_s), std::cos(2 * M_PI * f.t_s / period_s);
  return r;
}

}  // namespace rnav::bearing_effect
