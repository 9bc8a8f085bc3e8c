#include "common/physics/noise_process.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav {

std::string NoiseParams::kind() const {
  if (lambda <= 0) return "white";
  return lambda > 0.95 ? "gauss_markov" : "gauss_markov_plus_white";
}

void check_noise_params(const NoiseParams& p) {
  if (!(p.s2 > 0) || !(p.lambda >= 0 && p.lambda < 1) || !(p.tau_s > 0) || !(p.nom_share >= 0 && p.nom_share < 1) ||
      !(p.nom_tau_s > 0) || !(p.p_out >= 0 && p.p_out < 0.5) || !(p.s_out2 >= 0))
    throw std::invalid_argument(
        "NoiseParams out of range (s2 > 0, lambda and nom_share in [0, 1), tau and nom_tau > 0, p_out in [0, 0.5))");
}

Eigen::VectorXd sample_noise(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p,
                             std::mt19937_64& rng) {
  check_noise_params(p);
  if (!h.empty() && h.size() != t.size()) throw std::invalid_argument("sample_noise: gains != number of times");
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double q0 = p.nom_share * p.s2, q = (1 - p.nom_share) * p.lambda * p.s2, r = (1 - p.nom_share) * (1 - p.lambda) * p.s2;
  Eigen::VectorXd e(static_cast<Eigen::Index>(t.size()));
  double a = 0, g = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    // five draws per frame whatever the model, so that the stream stays aligned
    const double wa = N(rng), wg = N(rng), ww = N(rng), wo = N(rng), u = U(rng);
    if (i == 0) {
      a = std::sqrt(q0) * wa, g = std::sqrt(q) * wg;
    } else {
      const double dt = t[i] - t[i - 1];
      const double f0 = std::exp(-dt / p.nom_tau_s), f = std::exp(-dt / p.tau_s);
      a = f0 * a + std::sqrt(q0 * (1 - f0 * f0)) * wa;
      g = f * g + std::sqrt(q * (1 - f * f)) * wg;
    }
    double x = (h.empty() ? 1.0 : h[i]) * a + g + std::sqrt(r) * ww;
    if (p.p_out > 0 && u < p.p_out) x += std::sqrt(p.s_out2) * wo;
    e(static_cast<Eigen::Index>(i)) = x;
  }
  return e;
}

}  // namespace rnav
