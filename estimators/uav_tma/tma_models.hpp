// Pure models of the azimuth-only problem (no state, no I/O).
// State x = (north, east, v_north, v_east) of the object in frame F [m, m, m/s, m/s].
#pragma once

#include <Eigen/Dense>

namespace rnav::tma {

enum StateIndex : int { kN = 0, kE = 1, kVN = 2, kVE = 3, kDim = 4 };

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Row4 = Eigen::Matrix<double, 1, 4>;

/// Constant-velocity transition over dt:  p' = p + v dt,  v' = v.
Mat4 cv_transition(double dt_s);
/// Process noise of a white acceleration with spectral density q [m^2/s^3] per axis:
///   Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]] per axis.
Mat4 cv_process_noise(double q, double dt_s);

/// Bearing (the paper's A = arctan((z - z_uav)/(x - x_uav))), clockwise from north:
///   h(x) = atan2(e - e_o, n - n_o).
double bearing(const Vec4& x, const Eigen::Vector2d& p_obs_F);
/// Range D = hypot(n - n_o, e - e_o).
double range(const Vec4& x, const Eigen::Vector2d& p_obs_F);
/// dh/dx = [-(e - e_o)/D^2, (n - n_o)/D^2, 0, 0].
Row4 bearing_jacobian(const Vec4& x, const Eigen::Vector2d& p_obs_F);

/// Bearing noise variance: sensor sigma^2, plus the observer's own position error (sigma per
/// axis, white) seen across the line of sight at range D: sigma_nav^2 / D^2.
double bearing_variance(double sigma_bearing_rad, double sigma_nav_m, double range_m);

}  // namespace rnav::tma
