#include "common/physics/frames.hpp"

#include <GeographicLib/Geocentric.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace rnav {

namespace {
const GeographicLib::Geocentric& wgs84() { return GeographicLib::Geocentric::WGS84(); }

// R_ECEF_ENU at a point: GeographicLib's M (row-major) takes local ENU vectors into ECEF.
Eigen::Matrix3d R_ECEF_ENU(const Geodetic& at) {
  double X, Y, Z;
  std::vector<double> M(9);
  wgs84().Forward(at.lat_deg, at.lon_deg, at.h_m, X, Y, Z, M);
  Eigen::Matrix3d R;
  R << M[0], M[1], M[2], M[3], M[4], M[5], M[6], M[7], M[8];
  return R;
}

// ENU -> NED is a fixed axis permutation: (e, n, u) -> (n, e, -u).
Eigen::Matrix3d R_ENU_NED() {
  Eigen::Matrix3d R;
  R << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return R;
}
}  // namespace

LocalLevelFrame::LocalLevelFrame(const Geodetic& origin, double bearing_deg)
    : origin_(origin),
      bearing_deg_(bearing_deg),
      lc_(origin.lat_deg, origin.lon_deg, origin.h_m, GeographicLib::Geocentric::WGS84()) {
  const double b = bearing_deg * kDegToRad;
  // Rows are F's axes expressed in ENU (see the header).
  R_F_ENU_ << std::sin(b), std::cos(b), 0, 0, 0, 1, std::cos(b), -std::sin(b), 0;
  R_F_ECEF_ = R_F_ENU_ * R_ECEF_ENU(origin).transpose();
  wgs84().Forward(origin.lat_deg, origin.lon_deg, origin.h_m, o_ecef_.x(), o_ecef_.y(), o_ecef_.z());
}

Eigen::Isometry3d transform(const LocalLevelFrame& to, const LocalLevelFrame& from) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = to.R_F_ECEF() * from.R_F_ECEF().transpose();
  T.translation() = to.R_F_ECEF() * (from.origin_ecef() - to.origin_ecef());
  return T;
}

Eigen::Vector3d LocalLevelFrame::from_geodetic(const Geodetic& p) const {
  double e, n, u;
  lc_.Forward(p.lat_deg, p.lon_deg, p.h_m, e, n, u);
  return R_F_ENU_ * Eigen::Vector3d(e, n, u);
}

Geodetic LocalLevelFrame::to_geodetic(const Eigen::Vector3d& p_OP_F) const {
  const Eigen::Vector3d enu = R_F_ENU_.transpose() * p_OP_F;
  Geodetic g;
  lc_.Reverse(enu.x(), enu.y(), enu.z(), g.lat_deg, g.lon_deg, g.h_m);
  return g;
}

Eigen::Matrix3d R_ECEF_NED(const Geodetic& at) { return R_ECEF_ENU(at) * R_ENU_NED(); }

Eigen::Vector3d LocalLevelFrame::from_ned(const Geodetic& at, const Eigen::Vector3d& v_N) const {
  return R_F_ECEF_ * (R_ECEF_NED(at) * v_N);
}

Eigen::Vector3d LocalLevelFrame::to_ned(const Geodetic& at, const Eigen::Vector3d& v_F) const {
  return R_ECEF_NED(at).transpose() * (R_F_ECEF_.transpose() * v_F);
}

double wrap_pi(double a) {
  // Already in (-pi, pi]: remainder would return it unchanged (n = round(a / 2 pi) is 0, the tie
  // at a = pi rounding to even), so the call is skipped: bit for bit the same, and most angles
  // wrapped (innovations, residuals) are small.
  if (a > -M_PI && a <= M_PI) return a;
  a = std::remainder(a, 2 * M_PI);  // in [-pi, pi]
  return a <= -M_PI ? a + 2 * M_PI : a;
}

double nearest_wrapped(const std::vector<double>& angles_rad, double ref_rad) {
  double best = std::numeric_limits<double>::infinity();
  for (double a : angles_rad)
    if (std::abs(wrap_pi(a - ref_rad)) < std::abs(best)) best = wrap_pi(a - ref_rad);
  return best;
}

Polar polar_from_cartesian(const Eigen::Vector3d& p) {
  Polar q;
  const double h = std::hypot(p.x(), p.z());
  q.range_m = p.norm();
  q.course_rad = std::atan2(p.z(), p.x());
  q.glide_rad = std::atan2(p.y(), h);
  return q;
}

Eigen::Vector3d cartesian_from_polar(const Polar& q) {
  const double ch = std::cos(q.glide_rad);
  return {q.range_m * ch * std::cos(q.course_rad), q.range_m * std::sin(q.glide_rad),
          q.range_m * ch * std::sin(q.course_rad)};
}

Eigen::Matrix3d polar_jacobian(const Eigen::Vector3d& p) {
  const double x = p.x(), y = p.y(), z = p.z();
  const double h2 = x * x + z * z, h = std::sqrt(h2), D2 = h2 + y * y, D = std::sqrt(D2);
  Eigen::Matrix3d J;
  // dD/dp = p / D
  J.row(0) << x / D, y / D, z / D;
  // dEk/dp for Ek = atan2(z, x): (-z, 0, x) / h^2
  J.row(1) << -z / h2, 0, x / h2;
  // dEg/dp for Eg = atan2(y, h): (-x y / h, h, -z y / h) / D^2
  J.row(2) << -x * y / (h * D2), h / D2, -z * y / (h * D2);
  return J;
}

}  // namespace rnav
