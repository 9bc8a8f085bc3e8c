// The UAV's true path in frame F (x north, z east, y up): an orbit around a centre or a
// straight pass, at constant speed and altitude.
//   circle: theta(t) = theta0 + s V t / R (s = -1 ccw, +1 cw; theta = bearing from the centre),
//           p = c + R (cos theta, sin theta),  v = s V (-sin theta, cos theta)
//   straight: p = c_pass + V (t - T/2) (cos psi, sin psi), closest to the centre at T/2.
#pragma once

#include "common/physics/frames.hpp"
#include "sim/uav/observer_options.hpp"

#include <Eigen/Dense>

namespace rnav {

struct ObserverKinematics {
  Eigen::Vector2d p_OU_F;  ///< [m] (north, east)
  Eigen::Vector2d v_U_F;   ///< [m/s] (north, east)
  double course_rad = 0;   ///< [rad] course over ground, clockwise from north
};

class ObserverPath {
 public:
  /// @param centre_F    [m] orbit centre / point the straight pass passes by (north, east)
  /// @param duration_s  [s] scenario duration (the straight pass is centred on it)
  ObserverPath(const ObserverOptions& o, const Eigen::Vector2d& centre_F, double duration_s);
  ObserverKinematics at(double t_s) const;

 private:
  ObserverOptions o_;
  Eigen::Vector2d c_;
  double duration_s_;
};

}  // namespace rnav
