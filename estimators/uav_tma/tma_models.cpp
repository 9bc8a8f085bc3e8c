#include "tma_models.hpp"

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
  return std::atan2(x[kE] - o.y(), x[kN] - o.x());
}

double range(const Vec4& x, const Eigen::Vector2d& o) {
  return std::hypot(x[kN] - o.x(), x[kE] - o.y());
}

Row4 bearing_jacobian(const Vec4& x, const Eigen::Vector2d& o) {
  const double dn = x[kN] - o.x(), de = x[kE] - o.y(), d2 = dn * dn + de * de;
  Row4 H = Row4::Zero();
  H(kN) = -de / d2;
  H(kE) = dn / d2;
  return H;
}

double bearing_variance(double sb, double sn, double D) { return sb * sb + (sn * sn) / (D * D); }

}  // namespace rnav::tma
