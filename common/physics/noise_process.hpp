// A residual channel's noise process: its parameters (the model is written out in
// estimators/model_id/noise_model.hpp, which fits it) and one draw of it. Written once, so that
// the simulation injects exactly the noise the diagnosis identifies (sim/scene draws a recorded
// scene's channels with it; the diagnosis's parametric bootstrap draws its injections with it).
#pragma once

#include <Eigen/Dense>

#include <random>
#include <string>
#include <vector>

namespace rnav {

struct NoiseParams {
  double s2 = 1;         ///< marginal variance s^2 [unit^2], > 0
  double lambda = 0;     ///< correlated (Gauss-Markov) share of the non-nominal part, [0, 0.999]
  double tau_s = 1;      ///< its correlation time [s], > 0 (unused when lambda = 0)
  double nom_share = 0;  ///< mu: the nominal correlated component's share of s^2, [0, 0.999]
  double nom_tau_s = 1;  ///< tau0: its correlation time [s], > 0 (unused when mu = 0)
  double p_out = 0;      ///< outlier probability, [0, 0.5)
  double s_out2 = 0;     ///< outlier extra variance [unit^2], >= 0
  /// Of the further part: "white", "gauss_markov" (lambda > 0.95) or "gauss_markov_plus_white".
  std::string kind() const;
};

/// Throws std::invalid_argument naming the ranges when p is out of them.
void check_noise_params(const NoiseParams& p);

/// One draw of the noise model at the frame times t (gains h, empty: 1): the parametric
/// bootstrap's noise (injected_limits.hpp). Each part sampled exactly over irregular steps:
///   a_i = phi0 a_(i-1) + sqrt(q0 (1 - phi0^2)) w,  g_i = phi g_(i-1) + sqrt(q (1 - phi^2)) w',
///   e_i = h_i a_i + g_i + sqrt(r) w'',  a_0 ~ N(0, q0), g_0 ~ N(0, q) (stationary start),
/// and, with probability p_out, a further N(0, s_out^2) added (the contaminated normal).
Eigen::VectorXd sample_noise(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p,
                             std::mt19937_64& rng);

}  // namespace rnav
