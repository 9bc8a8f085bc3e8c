#include "sim/uav/observer_path.hpp"

#include <cmath>

namespace rnav {

ObserverPath::ObserverPath(const ObserverOptions& o, const Eigen::Vector2d& centre_F,
                           double duration_s)
    : o_(o), c_(centre_F), duration_s_(duration_s) {}

ObserverKinematics ObserverPath::at(double t_s) const {
  ObserverKinematics k;
  if (o_.path == "circle") {
    const double s = o_.direction == "cw" ? 1.0 : -1.0;
    const double th = o_.start_angle_deg * kDegToRad + s * o_.speed_mps * t_s / o_.radius_m;
    k.p_OU_F = c_ + o_.radius_m * Eigen::Vector2d(std::cos(th), std::sin(th));
    k.v_U_F = s * o_.speed_mps * Eigen::Vector2d(-std::sin(th), std::cos(th));
  } else {
    const double psi = o_.straight_heading_deg * kDegToRad;
    const Eigen::Vector2d u(std::cos(psi), std::sin(psi)), left(std::cos(psi - M_PI / 2), std::sin(psi - M_PI / 2));
    k.p_OU_F = c_ + o_.radius_m * left + o_.speed_mps * (t_s - duration_s_ / 2) * u;
    k.v_U_F = o_.speed_mps * u;
  }
  k.course_rad = std::atan2(k.v_U_F.y(), k.v_U_F.x());
  return k;
}

}  // namespace rnav
