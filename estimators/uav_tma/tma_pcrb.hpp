// Posterior Cramer-Rao lower bound for the azimuth-only problem (Tichavsky, Muravchik and
// Nehorai 1998), for the CV model with process noise q and bearing noise R:
//   J(k+1) = (Q(dt) + F(dt) J(k)^-1 F(dt)^T)^-1 + H(x_k+1)^T R^-1 H(x_k+1)
// with H evaluated at the true state (the expectation over a deterministic truth) and
// J(0) = P0^-1, the estimators' prior at the first bearing.
#pragma once

#include "estimators/uav_tma/tma_models.hpp"

namespace rnav::tma {

class TmaPcrb {
 public:
  explicit TmaPcrb(const Mat4& J0) : J_(J0) {}
  /// Time update over dt_s with white-acceleration density q [m^2/s^3].
  void predict(double dt_s, double q);
  /// Information of one bearing with Jacobian H (at the truth) and variance R.
  void update(const Row4& H, double R) { J_ += H.transpose() * H / R; }
  /// The bound on the estimate's covariance, J^-1.
  Mat4 bound() const { return J_.inverse(); }
  /// [m] bound on the position RMSE: sqrt(B_nn + B_ee).
  double pos_rmse_m() const;
  /// [m/s] bound on the velocity RMSE.
  double vel_rmse_mps() const;
  const Mat4& information() const { return J_; }

 private:
  Mat4 J_;
};

/// The EKF's prior covariance at the first bearing (see CartesianEkf), as information J0.
Mat4 prior_information(double bearing_rad, double range_m, double range_sigma_m,
                       double bearing_var, double vel_sigma_mps);

}  // namespace rnav::tma
