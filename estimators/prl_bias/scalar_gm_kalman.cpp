#include "estimators/prl_bias/scalar_gm_kalman.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav {

namespace {
double phi_of(double dt_s, double tau_s) { return std::isinf(tau_s) ? 1.0 : std::exp(-dt_s / tau_s); }
}  // namespace

ScalarGmKalman::ScalarGmKalman(double delta, double tau_s) : delta_(delta), tau_s_(tau_s) {
  if (!(delta > 0) || !std::isfinite(delta))
    throw std::invalid_argument("ScalarGmKalman: delta must be finite and > 0");
  if (!(tau_s > 0)) throw std::invalid_argument("ScalarGmKalman: tau_s must be > 0");
}

double ScalarGmKalman::update(double t_s, double chi, double r) {
  if (!(r > 0) || !std::isfinite(r) || !std::isfinite(chi))
    throw std::invalid_argument("ScalarGmKalman::update: r must be > 0 and chi finite");
  if (!init_) {
    init_ = true;
    eta_ = chi;
    p_ = r;
    t_s_ = t_s;
    return 1.0;
  }
  const double dt = t_s - t_s_;
  if (dt < 0) throw std::invalid_argument("ScalarGmKalman::update: time went backwards");
  t_s_ = t_s;
  const double phi = phi_of(dt, tau_s_);
  const double q = delta_ * delta_ * (1 - phi * phi);
  const double eta_bar = phi * eta_;          // prediction
  const double m = phi * phi * p_ + q;        // prediction variance (paper prints phi, not phi^2)
  const double K = m / (m + r);
  eta_ = eta_bar + K * (chi - eta_bar);
  p_ = (1 - K) * m;
  return K;
}

ScalarGmKalman::Steady ScalarGmKalman::steady_state(double delta, double tau_s, double dt_s,
                                                    double r) {
  const double phi = phi_of(dt_s, tau_s);
  const double q = delta * delta * (1 - phi * phi);
  const double b = r * (1 - phi * phi) - q;
  // positive root of m^2 + b m - q r = 0
  const double m = 0.5 * (-b + std::sqrt(b * b + 4 * q * r));
  const double K = m / (m + r);
  return {K, K * r, m};
}

}  // namespace rnav
