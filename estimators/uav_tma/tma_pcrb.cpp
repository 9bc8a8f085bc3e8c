#include "estimators/uav_tma/tma_pcrb.hpp"

#include <cmath>

namespace rnav::tma {

void TmaPcrb::predict(double dt, double q) {
  if (dt <= 0) return;
  const Mat4 F = cv_transition(dt);
  const Mat4 Q = cv_process_noise(q, dt);
  if (q == 0) {
    // J' = F^-T J F^-1 (no process noise: information is transported exactly)
    const Mat4 Fi = cv_transition(-dt);
    J_ = Fi.transpose() * J_ * Fi;
  } else {
    J_ = (Q + F * J_.inverse() * F.transpose()).inverse();
  }
  J_ = 0.5 * (J_ + J_.transpose());
}

double TmaPcrb::pos_rmse_m() const {
  const Mat4 B = bound();
  return std::sqrt(B(kN, kN) + B(kE, kE));
}

double TmaPcrb::vel_rmse_mps() const {
  const Mat4 B = bound();
  return std::sqrt(B(kVN, kVN) + B(kVE, kVE));
}

Mat4 prior_information(double b, double r0, double sr, double Rb, double sv) {
  const Eigen::Vector2d u(std::cos(b), std::sin(b)), c(-u.y(), u.x());
  Mat4 P = Mat4::Zero();
  P.topLeftCorner<2, 2>() = sr * sr * u * u.transpose() + r0 * r0 * Rb * c * c.transpose();
  P(kVN, kVN) = P(kVE, kVE) = sv * sv;
  return P.inverse();
}

}  // namespace rnav::tma
