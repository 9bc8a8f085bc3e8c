// The bearing of a line of sight in the local level plane, its rate and their Jacobians: the one
// definition the simulator (sim/uav), the estimators (estimators/uav_tma), the association and
// the diagnosis (estimators/diagnosis) and the importers use, beside the frames (frames.hpp has
// the landing radar's polar coordinates, polar_from_cartesian and polar_jacobian).
//
// Frame notation: d_NE = p_target - p_observer as (north, east) [m], in a local level frame whose
// x axis points north (the observer's own north where bearings are measured from it).
#pragma once

#include <Eigen/Dense>

#include <cmath>

namespace rnav {

/// beta = atan2(d_e, d_n) [rad], clockwise from north, in (-pi, pi]; 0 for d = 0.
inline double bearing_rad(const Eigen::Vector2d& d_NE) { return std::atan2(d_NE.y(), d_NE.x()); }

/// d beta / d d_NE = (-d_e, d_n) / |d|^2 [rad/m]; d must not be 0.
inline Eigen::RowVector2d bearing_jacobian(const Eigen::Vector2d& d_NE) {
  const double r2 = d_NE.squaredNorm();
  return Eigen::RowVector2d(-d_NE.y() / r2, d_NE.x() / r2);
}

/// d |d| / d d_NE = d / |d| [1]; d must not be 0.
inline Eigen::RowVector2d range_jacobian(const Eigen::Vector2d& d_NE) { return d_NE.transpose() / d_NE.norm(); }

/// The bearing's rate for a line of sight d_NE changing at v_NE = d(d_NE)/dt [m/s]:
/// beta_dot = (d_n v_e - d_e v_n) / |d|^2 [rad/s]; d must not be 0.
inline double bearing_rate_radps(const Eigen::Vector2d& d_NE, const Eigen::Vector2d& v_NE) {
  return (d_NE.x() * v_NE.y() - d_NE.y() * v_NE.x()) / d_NE.squaredNorm();
}

}  // namespace rnav
