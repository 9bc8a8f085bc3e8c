// The UAV's closed-loop guidance (uav.guidance = "los" or "estimate"): pure functions, so the
// law, its limits and the kinematics are tested on their own (test/test_guidance.cpp).
//
// Angles are courses/bearings clockwise from north [rad]; positions (north, east) [m] in F.
// Orbit sense s = +1 for "cw" (object on the right), -1 for "ccw" (object on the left).
//
// 1. Desired course from the line of sight (bearing beta to the object, range r if known):
//      chi_d = beta - s (pi/2 - atan(k (r - R) / R))
//    At r = R the course is perpendicular to the line of sight (the paper's condition); farther
//    out it turns towards the object, closer in away from it (k = standoff_gain; r unknown: the
//    offset is 0, pure perpendicular flight).
// 2. Heading for that course in the wind w (wind correction angle): with u = (cos chi_d,
//    sin chi_d) and w_perp = u x w (the cross-track wind component),
//      psi_d = chi_d - asin(w_perp / V_a).
// 3. Turn-rate command: omega = clamp(wrap(psi_d - psi) / tau + omega_ff, -omega_max, omega_max),
//      omega_ff = s V_a / R  (the turn rate of the orbit: course increases clockwise for cw),
//      omega_max = min(max_turn_rate, g tan(max_bank) / V_a).
// 4. Kinematics over dt at constant omega (exact): psi(t+dt) = psi + omega dt,
//      p(t+dt) = p + V_a (sin(psi+omega dt) - sin psi, cos psi - cos(psi+omega dt)) / omega + w dt
//    (straight-line limit V_a dt (cos psi, sin psi) + w dt as omega -> 0).
#pragma once

#include "common/physics/frames.hpp"
#include "sim/uav/observer_options.hpp"

#include <Eigen/Dense>

#include <optional>

namespace rnav::guidance {

/// [m/s^2] standard gravity, for the bank-angle turn-rate limit.
inline constexpr double kGravity = 9.80665;

/// The UAV's guided state.
struct UavState {
  Eigen::Vector2d p_OU_F = Eigen::Vector2d::Zero();  ///< [m] position (north, east)
  double heading_rad = 0;                            ///< [rad] heading (air-relative), clockwise from north
};

/// The guidance's constants, from ObserverOptions (checked there).
struct Limits {
  double airspeed_mps = 20;        ///< [m/s] V_a > 0
  double radius_m = 300;           ///< [m] R > 0, the standoff range
  double orbit_sense = -1;         ///< s: +1 cw, -1 ccw
  double standoff_gain = 1;        ///< k >= 0
  double time_constant_s = 2;      ///< tau > 0
  double max_turn_rate_radps = 0;  ///< omega_max > 0 (already the smaller of the two limits)
  Eigen::Vector2d wind_F = Eigen::Vector2d::Zero();  ///< [m/s] w, |w| < V_a
  static Limits from(const ObserverOptions& o);
};

/// 1: the desired course [rad] for a line of sight of bearing beta_rad and range r_m (nullopt:
/// unknown).
double desired_course(const Limits& l, double beta_rad, std::optional<double> r_m);
/// 2: the heading [rad] that makes good the course chi_rad in the wind.
double heading_for_course(const Limits& l, double chi_rad);
/// 3: the turn-rate command [rad/s], within +-max_turn_rate_radps.
double turn_rate_command(const Limits& l, double heading_rad, double desired_heading_rad);
/// 4: the state after dt_s at turn rate omega_radps.
UavState propagate(const Limits& l, const UavState& x, double omega_radps, double dt_s);
/// Ground velocity [m/s] (north, east) at heading psi: V_a (cos psi, sin psi) + w.
Eigen::Vector2d ground_velocity(const Limits& l, double heading_rad);

}  // namespace rnav::guidance
