// The noise model of one channel (a time series of residuals) and its innovations form.
//
// Model: e(t) = g(t) + w(t) with
//   g  Gauss-Markov (first-order, stationary): E g(t) g(t') = lambda s^2 exp(-|t - t'| / tau),
//   w  white:                                  E w^2 = (1 - lambda) s^2,
// so s^2 is the marginal variance, lambda in [0, 1) the correlated share (0: white; near 1:
// AR(1) sampled at the frame times) and tau [s] the correlation time. Irregular sampling and
// gaps are exact: between frames i-1 and i, phi_i = exp(-(t_i - t_(i-1)) / tau).
// Heavy tails: with probability p_out a frame is an outlier ~ N(0, S_i + s_out^2) instead
// (a contaminated normal: the outlier does not update the state g).
//
// Innovations form (the scalar Kalman filter of g):
//   g-_i = phi_i g+_(i-1),  P-_i = phi_i^2 P+_(i-1) + lambda s^2 (1 - phi_i^2),
//   nu_i = e_i - g-_i,      S_i  = P-_i + (1 - lambda) s^2,
//   g+_i = g-_i + K_i nu_i, P+_i = (1 - K_i) P-_i,  K_i = P-_i / S_i.
// The map e -> nu / sqrt(S) is linear with gains that depend only on the times, so applying it
// to the regressor columns as well turns generalised least squares into ordinary least squares
// (whiten()). The log-likelihood is -1/2 sum (nu^2 / S + log(2 pi S)).
#pragma once

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace rnav {

struct NoiseParams {
  double s2 = 1;         ///< marginal variance s^2 [unit^2], > 0
  double lambda = 0;     ///< correlated (Gauss-Markov) share of s^2, [0, 0.999]
  double tau_s = 1;      ///< correlation time [s], > 0 (unused when lambda = 0)
  double p_out = 0;      ///< outlier probability, [0, 0.5)
  double s_out2 = 0;     ///< outlier extra variance [unit^2], >= 0
  /// "white", "gauss_markov" (lambda > 0.95) or "gauss_markov_plus_white".
  std::string kind() const;
};

/// Whiten the rows of M (rows = frames of one channel in time order at times t) in place:
/// row i becomes (M_i - predicted from rows before) / sqrt(S_i). Rows with skip[i] (outliers,
/// empty when none) become zero and do not update the state. logS (if given) receives log S_i
/// (0 for skipped rows).
void whiten(const std::vector<double>& t, const NoiseParams& p, const std::vector<char>& skip,
            Eigen::Ref<Eigen::MatrixXd> M, Eigen::VectorXd* logS = nullptr);

/// Sequential (one-step-ahead predictive) log-likelihood of residuals e at times t under p,
/// summed over frames with score[i] (all when empty); every frame conditions the later ones
/// except those the mixture judges outliers (posterior outlier probability > 1/2).
double predictive_loglik(const std::vector<double>& t, const std::vector<double>& e, const NoiseParams& p,
                         const std::vector<char>& score = {});

}  // namespace rnav
