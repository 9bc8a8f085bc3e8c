// Scalar Kalman filter for a first-order Gauss-Markov bias observed in white noise
// (docs/method.md section 1, equations (7)-(11) with the paper's slips corrected):
//   model:       eta(k+1) = phi eta(k) + w(k),  phi = exp(-dt/T),  q = Var w = delta^2 (1 - phi^2)
//   observation: chi(k) = eta(k) + omega(k),    Var omega = r(k)
//   predict:     eta_bar = phi eta_hat,   m = phi^2 p + q
//   update:      K = m / (m + r),  eta_hat = eta_bar + K (chi - eta_bar),  p = (1 - K) m = K r
// Initialisation (paper): eta_hat = chi(1) with variance r(1) -- the estimate one observation
// gives from an uninformative prior, so chi(1) is not counted twice.
#pragma once

namespace rnav {

class ScalarGmKalman {
 public:
  /// @param delta  stationary 1-sigma of the bias [unit of eta], > 0
  /// @param tau_s  correlation time T [s], > 0 (infinity: a random constant)
  ScalarGmKalman(double delta, double tau_s);

  /// Process one pseudo-measurement chi with noise variance r > 0 at time t_s (non-decreasing).
  /// Returns the gain used (1 for the initialising observation).
  double update(double t_s, double chi, double r);
  bool initialized() const { return init_; }
  double eta() const { return eta_; }  ///< current estimate eta_hat
  double p() const { return p_; }      ///< its variance
  void reset() { init_ = false; eta_ = p_ = 0; }

  /// Steady state for a constant step: prediction variance m solves
  ///   m^2 + m (r (1 - phi^2) - q) - q r = 0,
  /// K = m / (m + r), p = K r. Returns {K, p}.
  struct Steady {
    double gain, p, m;
  };
  static Steady steady_state(double delta, double tau_s, double dt_s, double r);

 private:
  double delta_, tau_s_;
  bool init_ = false;
  double eta_ = 0, p_ = 0, t_s_ = 0;
};

}  // namespace rnav
