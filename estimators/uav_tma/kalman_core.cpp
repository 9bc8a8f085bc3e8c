#include "estimators/uav_tma/kalman_core.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav::tma {

void predict(Gaussian& g, const Mat4& F, const Mat4& Q) {
  g.x = F * g.x;
  g.P = F * g.P * F.transpose() + Q;
  g.P = 0.5 * (g.P + g.P.transpose());
}

ScalarUpdate update(Gaussian& g, double nu, const Row4& H, double R) {
  const double S = (H * g.P * H.transpose())(0, 0) + R;
  if (!(S > 0) || !std::isfinite(nu)) throw std::runtime_error("Kalman update: S <= 0 or residual not finite");
  const Vec4 K = g.P * H.transpose() / S;
  g.x += K * nu;
  const Mat4 IKH = Mat4::Identity() - K * H;
  g.P = IKH * g.P * IKH.transpose() + K * R * K.transpose();
  g.P = 0.5 * (g.P + g.P.transpose());
  if (!g.x.allFinite() || !g.P.allFinite()) throw std::runtime_error("Kalman update: state not finite");
  ScalarUpdate u;
  u.S = S;
  u.nis = nu * nu / S;
  u.log_lik = -0.5 * (u.nis + std::log(2 * M_PI * S));
  return u;
}

}  // namespace rnav::tma
