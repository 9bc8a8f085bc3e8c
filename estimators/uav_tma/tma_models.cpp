#include "estimators/uav_tma/tma_models.hpp"

#include "common/physics/bearing.hpp"
#include <cmath>

namespace rnav::tma {

Mat4 cv_transition(double dt) {
  Mat4 F = Mat4::Identity();
  F(kN, kVN) = dt;
  F(kE, kVE) = dt;
  return F;
}

Mat4 cv_process_noise(double q, double dt) {
  Mat4 Q = Mat4::Zero();
  const double a = q * dt * dt * dt / 3, b = q * dt * dt / 2, c = q * dt;
  Q(kN, kN) = Q(kE, kE) = a;
  Q(kN, kVN) = Q(kVN, kN) = Q(kE, kVE) = Q(kVE, kE) = b;
  Q(kVN, kVN) = Q(kVE, kVE) = c;
  return Q;
}

double bearing(const Vec4& x, const Eigen::Vector2d& o) {
  return bearing_rad(Eigen::Vector2d(x[kN] - o.x(), x[kE] - o.y()));
}

double range(const Vec4& x, const Eigen::Vector2d& o) {
  return std::hypot(x[kN] - o.x(), x[kE] - o.y());
}

Row4 bearing_jacobian(const Vec4& x, const Eigen::Vector2d& o) {
  const Eigen::RowVector2d g = rnav::bearing_jacobian(Eigen::Vector2d(x[kN] - o.x(), x[kE] - o.y()));
  Row4 H = Row4::Zero();
  H(kN) = g(0);
  H(kE) = g(1);
  return H;
}

double bearing_variance(double sb, double sn, double D) { return sb * sb + (sn * sn) / (D * D); }

}  // namespace rnav::tma
