// The landing radar's deterministic catalogue effects, written once: each effect's contribution
// to one plot's polar error zeta = (range D [m], course Ek [rad], glide Eg [rad]) is
//   d zeta = C(plot) theta,
// C a 3 x k matrix of the plot's geometry and theta the effect's k parameters. The simulator
// injects C theta (sim/prl/prl_error_model.cpp, GeometricEffects) and the diagnosis fits theta on
// the same C (estimators/diagnosis/prl_diagnose.cpp), so what one can hide the other can name.
// The stochastic entries (noise_scale, correlated_noise, outliers) are noise models, not columns.
// Frames as in frames.hpp: R is the radar frame (x along the azimuth reference, y up, z right).
#pragma once

#include <Eigen/Dense>

namespace rnav::prl_effect {

/// The rows of C: the polar channels.
enum Channel { kRange = 0, kCourse = 1, kGlide = 2, kChannels = 3 };

/// What the columns need of one plot.
struct PlotGeometry {
  double t_s = 0;             ///< [s] time of validity, sim time since the flight's start
  double range_m = 0;         ///< [m] slant range D of the aircraft A from the radar R, > 0
  double glide_rad = 0;       ///< [rad] glide (elevation) angle Eg, in (-pi/2, pi/2), not 0 for refraction
  Eigen::Matrix3d J;          ///< d(D, Ek, Eg)/d p_RA_R [m/m, rad/m, rad/m] (frames.hpp polar_jacobian)
  Eigen::Vector3d rate;       ///< d(D, Ek, Eg)/dt = J v_A_R [m/s, rad/s, rad/s]
};

/// range_gain, theta = g [1]: dD = g D.
Eigen::Vector3d range_gain(const PlotGeometry& g);
/// time_offset, theta = tau [s] (radar stamp minus true time): a plot stamped t was taken at
/// t - tau, so d zeta = zeta(t - tau) - zeta(t) = -zeta_dot tau (first order).
Eigen::Vector3d time_offset(const PlotGeometry& g);
/// elevation_refraction, theta = k [rad]: dEg = k cot(Eg).
Eigen::Vector3d elevation_refraction(const PlotGeometry& g);
/// azimuth_elevation_coupling, theta = c [rad]: dEk = c tan(Eg).
Eigen::Vector3d azimuth_elevation_coupling(const PlotGeometry& g);
/// site_offset, theta = (east, north, up) [m] of the surveyed site minus the true one: the radar
/// measures from the true site, so p_meas = p_RA + delta and d zeta = J R_R_ENU delta_ENU (first
/// order, |delta| << D).
Eigen::Matrix3d site_offset(const PlotGeometry& g, const Eigen::Matrix3d& R_R_ENU);
/// bias_drift in `channel`, theta = its rate [m/s or rad/s]: d zeta_c = theta (t - t0_s).
Eigen::Vector3d bias_drift(const PlotGeometry& g, int channel, double t0_s);
/// bias_step in `channel` at t_step_s [s], theta = its size [m or rad]: d zeta_c = theta 1[t >= t_step].
Eigen::Vector3d bias_step(const PlotGeometry& g, int channel, double t_step_s);
/// periodic in `channel` of period_s [s] > 0, theta = (a_sin, a_cos) [m or rad]:
/// d zeta_c = a_sin sin(2 pi t / P) + a_cos cos(2 pi t / P).
Eigen::Matrix<double, 3, 2> periodic(const PlotGeometry& g, int channel, double period_s);

/// (east, north, up) -> R for a radar whose azimuth reference points `azimuth_reference_deg`
/// [deg] clockwise from north: x = (sin b, cos b, 0), y = up, z = (cos b, -sin b, 0) in ENU.
Eigen::Matrix3d R_R_ENU(double azimuth_reference_deg);

}  // namespace rnav::prl_effect
