// The one place that changes a Gaussian state estimate (x, P): prediction and a scalar update
// in Joseph form, P kept symmetric.
#pragma once

#include "estimators/uav_tma/tma_models.hpp"

namespace rnav::tma {

struct Gaussian {
  Vec4 x = Vec4::Zero();
  Mat4 P = Mat4::Identity();
};

/// x <- F x;  P <- F P F^T + Q.
void predict(Gaussian& g, const Mat4& F, const Mat4& Q);

struct ScalarUpdate {
  double nis = 0;      ///< nu^2 / S
  double log_lik = 0;  ///< log N(nu; 0, S)
  double S = 0;        ///< innovation variance
};
/// Update with residual nu = z - h(x) (already wrapped), Jacobian H, noise variance R > 0:
///   S = H P H^T + R,  K = P H^T / S,  x <- x + K nu,
///   P <- (I - K H) P (I - K H)^T + K R K^T   (Joseph form), then symmetrised.
/// Throws std::runtime_error if S is not positive or the result is not finite.
ScalarUpdate update(Gaussian& g, double nu, const Row4& H, double R);

}  // namespace rnav::tma
