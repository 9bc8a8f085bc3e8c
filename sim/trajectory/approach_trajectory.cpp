#include "sim/trajectory/approach_trajectory.hpp"

#include <cmath>

namespace rnav {

namespace {
constexpr double kG = 9.80665;  // [m/s^2] standard gravity

Eigen::Vector2d rotate(const Eigen::Vector2d& v, double a) {
  return {v.x() * std::cos(a) - v.y() * std::sin(a), v.x() * std::sin(a) + v.y() * std::cos(a)};
}
}  // namespace

ApproachTrajectory::ApproachTrajectory(const TrajectoryOptions& o) : o_(o) {
  p0_ = {o.start_x_m, o.start_z_m};
  const Eigen::Vector2d intercept(o.intercept_x_m, 0.0);
  d2_ = {-1.0, 0.0};  // final: along -x towards the threshold
  const Eigen::Vector2d to_i = intercept - p0_;
  if (to_i.norm() < 1.0)
    throw ConfigError("trajectory: start lies on the intercept point; move trajectory.intercept_x_m");
  d1_ = to_i.normalized();
  // r = V^2 / (g tan(bank))
  radius_m_ = o.speed_mps * o.speed_mps / (kG * std::tan(o.bank_deg * kDegToRad));
  const double turn = std::acos(std::clamp(d1_.dot(d2_), -1.0, 1.0));  // heading change
  if (turn > 170.0 * kDegToRad)
    throw ConfigError("trajectory: the first leg points away from final (turn > 170 deg); "
                      "check trajectory.start_x_m and trajectory.intercept_x_m");
  // Arc tangent to both legs: tangent points at L = r tan(turn/2) from the intercept point.
  const double lead = radius_m_ * std::tan(turn / 2);
  if (lead > to_i.norm())
    throw ConfigError("trajectory: the turn onto final (radius " + std::to_string(radius_m_) +
                      " m) does not fit between the start and the intercept point; increase "
                      "trajectory.bank_deg or move trajectory.intercept_x_m");
  t1_ = intercept - d1_ * lead;
  t2_ = intercept + d2_ * lead;
  len1_m_ = (t1_ - p0_).norm();
  arc_len_m_ = radius_m_ * turn;
  // Turn direction: sign of the 2-D cross product d1 x d2.
  turn_sign_ = (d1_.x() * d2_.y() - d1_.y() * d2_.x()) >= 0 ? 1.0 : -1.0;
  centre_ = t1_ + turn_sign_ * radius_m_ * Eigen::Vector2d(-d1_.y(), d1_.x());

  tan_glide_ = std::tan(o.glide_deg * kDegToRad);
  // Glide path: y = (x - aim_x) tan(glide); the level leg at start_y meets it at descent_x.
  descent_x_m_ = o.aim_x_m + o.start_y_m / tan_glide_;
  if (descent_x_m_ > t2_.x())
    throw ConfigError("trajectory: the descent would begin (x = " + std::to_string(descent_x_m_) +
                      " m) before the aircraft is established on final (x = " +
                      std::to_string(t2_.x()) + " m); move trajectory.intercept_x_m out");
  if (o.end_x_m >= t2_.x())
    throw ConfigError("trajectory: trajectory.end_x_m lies before the turn onto final ends");
  duration_s_ = (len1_m_ + arc_len_m_ + (t2_.x() - o.end_x_m)) / o.speed_mps;
}

AircraftKinematics ApproachTrajectory::at(double t_s) const {
  const double V = o_.speed_mps;
  const double s = std::clamp(t_s, 0.0, duration_s_) * V;  // horizontal path length
  Eigen::Vector2d p, v;
  if (s <= len1_m_) {
    p = p0_ + d1_ * s;
    v = d1_ * V;
  } else if (s <= len1_m_ + arc_len_m_) {
    const double ang = turn_sign_ * (s - len1_m_) / radius_m_;
    p = centre_ + rotate(t1_ - centre_, ang);
    v = rotate(d1_, ang) * V;
  } else {
    p = t2_ + d2_ * (s - len1_m_ - arc_len_m_);
    v = d2_ * V;
  }
  AircraftKinematics k;
  // Level at start_y until x = descent_x on final, then y = (x - aim_x) tan(glide).
  const bool descending = s > len1_m_ + arc_len_m_ && p.x() < descent_x_m_;
  const double y = descending ? (p.x() - o_.aim_x_m) * tan_glide_ : o_.start_y_m;
  const double vy = descending ? v.x() * tan_glide_ : 0.0;
  k.p_TA_L = {p.x(), y, p.y()};
  k.v_A_L = {v.x(), vy, v.y()};
  return k;
}

}  // namespace rnav
