// The surface object's true horizontal motion in frame F (x north, z east): constant velocity,
// with scripted manoeuvres (turn rate and acceleration over an interval). Deterministic.
#pragma once

#include "common/physics/frames.hpp"
#include "sim/target/target_options.hpp"

#include <Eigen/Dense>

namespace rnav {

struct TargetKinematics {
  Eigen::Vector2d p_OT_F;  ///< [m] (north, east)
  Eigen::Vector2d v_T_F;   ///< [m/s] (north, east)
};

class TargetMotion {
 public:
  /// @param step_s  integration step [s] (the truth grid); manoeuvre boundaries are exact
  TargetMotion(const TargetOptions& o, double step_s);
  /// State at t_s >= 0 (integrated from 0; queries must not go backwards in time for speed,
  /// but any t_s is answered exactly the same way).
  TargetKinematics at(double t_s) const;

 private:
  TargetOptions o_;
  double step_s_;
};

}  // namespace rnav
