// The aircraft's approach path in the landing frame L (see TrajectoryOptions for the geometry).
#pragma once

#include "sim/trajectory/trajectory.hpp"

#include <Eigen/Dense>

namespace rnav {

class ApproachTrajectory : public Trajectory {
 public:
  /// Throws ConfigError when the path cannot be flown as specified (turn too wide for the
  /// intercept geometry, descent starting before the aircraft is on final, ...).
  explicit ApproachTrajectory(const TrajectoryOptions& o);

  /// State at time t_s in [0, duration_s()] (clamped outside).
  AircraftKinematics at(double t_s) const override;
  /// [s] time at which the aircraft reaches x = end_x_m on final.
  double duration_s() const override { return duration_s_; }
  /// [m] turn radius r = V^2 / (g tan(bank)).
  double turn_radius_m() const { return radius_m_; }
  /// [m] x where the descent begins (level leg ends).
  double descent_x_m() const { return descent_x_m_; }
  /// [s] time the turn onto final ends.
  double final_time_s() const { return (len1_m_ + arc_len_m_) / o_.speed_mps; }

 private:
  TrajectoryOptions o_;
  // Horizontal geometry in the (x, z) plane of L.
  Eigen::Vector2d p0_, d1_, d2_, t1_, t2_, centre_;
  double len1_m_ = 0, arc_len_m_ = 0, radius_m_ = 0, turn_sign_ = 1;
  double descent_x_m_ = 0, tan_glide_ = 0, duration_s_ = 0;
};

}  // namespace rnav
