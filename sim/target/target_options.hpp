// Options of the surface object's motion (UAV scenario section "target"), with their keys and checks.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// The surface object. Constant velocity unless manoeuvres are scripted.
struct TargetOptions {
  double start_north_m = 0;   ///< [m] first position from the origin
  double start_east_m = 0;    ///< [m]
  double speed_mps = 1.0;     ///< [m/s] initial speed, [0, 30]
  double heading_deg = 45;    ///< [deg] initial course, clockwise from north
  /// Manoeuvres, each [t_s, duration_s, turn_rate_dps, accel_mps2]: from t_s for duration_s the
  /// course changes at turn_rate_dps (deg/s, clockwise positive) and the speed at accel_mps2.
  std::vector<std::array<double, 4>> manoeuvres;
};
/// Throws ConfigError (naming target.manoeuvres) unless each has t_s >= 0 and duration_s > 0.
void check_target(const TargetOptions& o);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(TargetOptions& o, V& v) {
  v.num("start_north_m", o.start_north_m, -1e5, 1e5);
  v.num("start_east_m", o.start_east_m, -1e5, 1e5);
  v.num("speed_mps", o.speed_mps, 0, 30);
  v.num("heading_deg", o.heading_deg, -360, 360);
  v.quads("manoeuvres", o.manoeuvres);
}

}  // namespace options_io
}  // namespace rnav
