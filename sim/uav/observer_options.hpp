// Options of the UAV's path, guidance and navigation error (UAV scenario sections "uav" and
// "uav_nav"), with their keys.
#pragma once

#include "common/io/options_io.hpp"
#include "common/io/tma_estimator_names.hpp"

namespace rnav {

/// The UAV's path and guidance.
///  - guidance "orbit" (default): the prescribed ground track of `path` (today's paper figures):
///    a circle about the object's first position (+ offset) or a straight pass. Wind and the
///    turn limits do not apply (the track is flown exactly).
///  - guidance "los": line-of-sight guidance from the measured bearing (sim/uav/guidance.hpp):
///    the course is kept perpendicular to the last measured bearing (object on the left for
///    "ccw", on the right for "cw"), corrected towards radius_m by the estimator's range when it
///    has one (the estimate of `guidance_estimator`, estimate_latency_s old).
///  - guidance "estimate": an orbit of radius_m about the estimator's position estimate
///    (predicted to the current time with its velocity), estimate_latency_s old.
///  Closed loop (los, estimate): the UAV flies at airspeed speed_mps in the constant wind, its
///  turn rate limited by max_bank_deg and max_turn_rate_dps; it starts where the orbit would.
struct ObserverOptions {
  std::string path = "circle";   ///< "circle" (orbit) or "straight" (a pass by the object); guidance "orbit" only
  double radius_m = 300;         ///< [m] orbit radius / standoff range; straight: distance of closest approach, [20, 20000]
  double speed_mps = 20;         ///< [m/s] orbit: ground speed; los, estimate: airspeed, [1, 200]
  std::string guidance = "orbit";        ///< "orbit", "los" or "estimate" (see above)
  double max_bank_deg = 30;              ///< [deg] bank limit: turn rate <= g tan(bank) / airspeed, (0, 80]
  double max_turn_rate_dps = 20;         ///< [deg/s] turn-rate limit of the airframe, (0, 180]
  double heading_time_constant_s = 2;    ///< [s] heading loop: rate command = heading error / this (+ feed-forward), [0.1, 100]
  double standoff_gain = 1;              ///< range law: course offset atan(gain (r - radius) / radius) towards the object, [0, 10]
  double wind_north_mps = 0;             ///< [m/s] constant wind (air mass velocity), north, |w| < airspeed
  double wind_east_mps = 0;              ///< [m/s] constant wind, east
  double estimate_latency_s = 1;         ///< [s] age of the estimate guidance uses (estimator + link); runner.window_s <= this, [0.01, 100]
  std::string guidance_estimator = "rpekf";  ///< the estimator (UAV_TMA's `estimator`) whose estimate guidance uses
  double altitude_m = 150;       ///< [m] height above the origin's ellipsoidal height, [0, 5000]
  std::string direction = "ccw"; ///< orbit direction seen from above: "ccw" or "cw"
  double centre_offset_north_m = 0;  ///< [m] orbit centre (straight: point of closest approach) from the object's first position
  double centre_offset_east_m = 0;   ///< [m]
  double start_angle_deg = 180;  ///< [deg] circle: bearing from the centre to the UAV's start
  double straight_heading_deg = 90;  ///< [deg] straight: the UAV's course
};

/// The UAV's SNS/INS position error (horizontal, per axis) as used for the bearing's origin.
struct ObserverNavOptions {
  double white_sigma_m = 0.3;   ///< [m] white part, 1 sigma per axis
  double corr_sigma_m = 0.0;    ///< [m] time-correlated (Gauss-Markov) part, 1 sigma per axis
  double corr_tau_s = 60;       ///< [s] its correlation time
  double vel_sigma_mps = 0.05;  ///< [m/s] velocity error per axis, white
};
/// The UAV's guidance uses the estimator's output (UAV_TMA), i.e. guidance is "los" or "estimate".
inline bool closed_loop(const ObserverOptions& o) { return o.guidance != "orbit"; }
/// [s] one orbit: 2 pi R / V.
double orbit_period_s(const ObserverOptions& o);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(ObserverOptions& o, V& v) {
  v.choice("path", o.path, {"circle", "straight"});
  v.num("radius_m", o.radius_m, 20, 20000);
  v.num("speed_mps", o.speed_mps, 1, 200);
  v.num("altitude_m", o.altitude_m, 0, 5000);
  v.choice("direction", o.direction, {"ccw", "cw"});
  v.num("centre_offset_north_m", o.centre_offset_north_m, -1e5, 1e5);
  v.num("centre_offset_east_m", o.centre_offset_east_m, -1e5, 1e5);
  v.num("start_angle_deg", o.start_angle_deg, -360, 360);
  v.num("straight_heading_deg", o.straight_heading_deg, -360, 360);
  v.choice("guidance", o.guidance, {"orbit", "los", "estimate"});
  v.num("max_bank_deg", o.max_bank_deg, 1e-3, 80);
  v.num("max_turn_rate_dps", o.max_turn_rate_dps, 1e-3, 180);
  v.num("heading_time_constant_s", o.heading_time_constant_s, 0.1, 100);
  v.num("standoff_gain", o.standoff_gain, 0, 10);
  v.num("wind_north_mps", o.wind_north_mps, -100, 100);
  v.num("wind_east_mps", o.wind_east_mps, -100, 100);
  v.num("estimate_latency_s", o.estimate_latency_s, 0.01, 100);
  v.choice("guidance_estimator", o.guidance_estimator, tma_estimator_names());
}

template <class V> void visit(ObserverNavOptions& o, V& v) {
  v.num("white_sigma_m", o.white_sigma_m, 0, 100);
  v.num("corr_sigma_m", o.corr_sigma_m, 0, 100);
  v.num("corr_tau_s", o.corr_tau_s, 0.01, kInf);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 0, 10);
}

}  // namespace options_io
}  // namespace rnav
