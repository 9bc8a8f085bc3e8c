// The multi-sensor catalogue's deterministic effects, written once: each effect's contribution
// to one detection's residual (measured minus predicted from the reference) is
//   d y = c(geometry) theta,
// c a row of the detection's geometry and theta the effect's parameters (the catalogue's
// units: s, rad, m, 1). The diagnosis fits theta on these columns
// (estimators/diagnosis/multi_problem.cpp) and the recorded-scene simulation injects c theta
// (sim/scene), so what one names the other makes. The stochastic findings (noise_scale,
// correlated_noise, outliers) are noise models (common/physics/noise_process.hpp), not columns;
// target_maneuver is the reference track's own and is replayed with it.
//
// Geometry in the observer's local level orientation at the detection's time, 2-D (east, north)
// or (north, east) alike as long as every vector uses the same axes: d the target's position
// from the observer, dh the measurement's Jacobian with respect to d (range: d' / |d|; bearing:
// the bearing's gradient), v_rel the target's velocity relative to the observer, v_target its
// own, u the unit vector along its course (zero where it is too slow to have one) and u_perp to
// its starboard.
#pragma once

#include "common/physics/scan_stamp.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rnav::multi_effect {

/// What the columns need of one detection, as a range or as a bearing observation.
struct Geometry {
  bool is_range = false;          ///< a range observation (else a bearing)
  Eigen::RowVector2d dh = Eigen::RowVector2d::Zero();  ///< d h / d d: range [m/m], bearing [rad/m]
  Eigen::Vector2d v_rel = Eigen::Vector2d::Zero();     ///< [m/s] target minus observer velocity
  Eigen::Vector2d v_target = Eigen::Vector2d::Zero();  ///< [m/s] the target's velocity
  Eigen::Vector2d u = Eigen::Vector2d::Zero();         ///< unit vector along its course; zero below min speed
  Eigen::Vector2d u_perp = Eigen::Vector2d::Zero();    ///< u turned to starboard
  double range_pred = 0;          ///< [m] predicted range |d|
  double bearing_pred = 0;        ///< [rad] predicted bearing, clockwise from north
  double t = 0;                   ///< [s] the detection's time
};

inline Eigen::RowVectorXd one(double x) { return Eigen::RowVectorXd::Constant(1, x); }

/// bearing_bias, range_bias, echo_range_offset: theta = b [rad or m]: dy = b.
inline Eigen::RowVectorXd constant(const Geometry&) { return one(1.0); }

/// time_offset, theta = tau [s] (the sensor's stamp minus true time): a detection stamped t
/// shows the target where it was at t - tau, dy = -dh v_rel tau (first order).
inline Eigen::RowVectorXd sensor_clock(const Geometry& g) { return one(-g.dh * g.v_rel); }

/// truth_time_offset, theta = tau [s] (the reference's stamp minus true time): the reference
/// at t shows the target at t - tau, so the prediction lags and dy = dh v_target tau.
inline Eigen::RowVectorXd reference_clock(const Geometry& g) { return one(g.dh * g.v_target); }

/// antenna_offset, theta = (along_m, starboard_m): the point the sensor sees lies this far
/// ahead of and to starboard of the reference's antenna, dy = dh (along u + starboard u_perp).
inline Eigen::RowVectorXd hull_offset(const Geometry& g) {
  Eigen::RowVectorXd r(2);
  r << g.dh * g.u, g.dh * g.u_perp;
  return r;
}

/// range_gain, theta = k [1]: dy = k |d|.
inline Eigen::RowVectorXd range_gain(const Geometry& g) { return one(g.range_pred); }

/// near_side_echo, theta = (a, b) [m], the hull's half-length and half-beam: the echo lies short
/// of the hull's centre by the rectangle's support function along the line of sight,
/// dy = -(a |dh u| + b |dh u_perp|) (dh of a range is the unit line of sight).
inline Eigen::RowVectorXd near_side(const Geometry& g) {
  Eigen::RowVectorXd c(2);
  c << -std::abs(g.dh * g.u), -std::abs(g.dh * g.u_perp);
  return c;
}

/// scan_time_offset of a sensor turning clockwise once per period_s [s] and stamping each scan
/// at its sweep's end bearing sweep_end_rad: theta = (c_s, sweep_frac),
/// dt = c + f sweep_delay_s(beta, sweep_end, period), dy = -dh v_rel dt.
inline Eigen::RowVectorXd scan_stamp(const Geometry& g, double sweep_end_rad, double period_s) {
  const double r = -g.dh * g.v_rel;
  Eigen::RowVectorXd row(2);
  row << r, r * sweep_delay_s(g.bearing_pred, sweep_end_rad, period_s);
  return row;
}

/// bias_step at step_time_s [s], theta = b [rad]: dy = b from that time on.
inline Eigen::RowVectorXd step(const Geometry& g, double step_time_s) { return one(g.t >= step_time_s ? 1.0 : 0.0); }

/// The catalogue's entry names with a column here, in the catalogue's order.
inline const std::vector<std::string>& names() {
  static const std::vector<std::string> n{"time_offset",      "bearing_bias",   "bias_step",         "range_bias",
                                          "echo_range_offset", "near_side_echo", "range_gain",        "scan_time_offset",
                                          "truth_time_offset", "antenna_offset"};
  return n;
}

/// Whether entry `name` acts on a range (is_range) or on a bearing: bearing_bias and bias_step
/// on bearings only; range_bias, echo_range_offset, near_side_echo and range_gain on ranges
/// only; the clocks, scan stamps and antenna offsets on both.
inline bool acts_on(const std::string& name, bool is_range) {
  if (name == "bearing_bias" || name == "bias_step") return !is_range;
  if (name == "range_bias" || name == "echo_range_offset" || name == "near_side_echo" || name == "range_gain") return is_range;
  return true;
}

/// The columns of entry `name` for geometry g (empty where it does not act on g's quantity).
/// scan_value: the scanned value of a scanned entry (bias_step: its time [s]; scan_time_offset:
/// its sweep's end bearing [deg]); period_s: the sensor's scan period [s] (scan_time_offset).
/// Throws std::invalid_argument for a name without a column.
inline Eigen::RowVectorXd columns(const std::string& name, const Geometry& g, double scan_value = 0, double period_s = 0) {
  if (!acts_on(name, g.is_range)) return {};
  if (name == "bearing_bias" || name == "range_bias" || name == "echo_range_offset") return constant(g);
  if (name == "time_offset") return sensor_clock(g);
  if (name == "truth_time_offset") return reference_clock(g);
  if (name == "antenna_offset") return hull_offset(g);
  if (name == "range_gain") return range_gain(g);
  if (name == "near_side_echo") return near_side(g);
  if (name == "scan_time_offset") return scan_stamp(g, scan_value * M_PI / 180, period_s);
  if (name == "bias_step") return step(g, scan_value);
  throw std::invalid_argument("multi-sensor effect '" + name + "' has no column (a noise finding or the reference's own)");
}

}  // namespace rnav::multi_effect
