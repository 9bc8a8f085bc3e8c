// Identify a channel's noise model (noise_model.hpp) by restricted maximum likelihood.
//
// The fixed effects X (a quadratic trend in time, the nuisance and the effects chosen so far,
// restricted to the channel) are estimated by GLS inside the likelihood, and REML's
// -1/2 log|X~' X~| term is kept, so a slow mean effect (bias, drift, a step) is not taken for
// correlated noise. For each (lambda, tau) the scale s^2 is profiled out in closed form:
//   l_R = -1/2 [ n' log(RSS / n') + sum log S~_i + log|X~' X~| + n' (1 + log 2 pi) ],
// n' = n - rank(X), S~ the innovation variances for s^2 = 1. Search: a log grid of tau in
// [tau_min_s, min(tau_max_s, span / tau_span_divisor)] by a grid of lambda, then a trust-region
// Newton ascent in (log tau, logit lambda) from the grid's best point (box_ascent.hpp). White noise is the model lambda = 0; the correlated model is kept
// when 2 (l_corr - l_white) exceeds the chi-square(2) quantile at alpha_correlated; it departs
// from the nominal model (white, or a stated Gauss-Markov share) when 2 (l_corr - l_nominal) does.
// Outliers: frames whose standardized innovation exceeds z_outlier are flagged and the model is
// refitted without them (they do not update the state), until the flags settle.
#pragma once

#include <stdexcept>

#include "estimators/model_id/noise_model.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <vector>

namespace rnav {

struct NoiseIdOptions {
  double tau_min_s = 0.05;        ///< [s] shortest correlation time searched, > 0
  double tau_max_s = 600;         ///< [s] longest, further limited to span / tau_span_divisor
  double tau_span_divisor = 4;    ///< a correlation longer than span / 4 is a slow mean effect here
  double alpha_correlated = 0.01; ///< level of the white-vs-correlated test, (0, 0.5)
  bool flag_outliers = true;      ///< flag and refit (the caller decides whether to keep the mixture)
  double expected_false_flags = 0.05;  ///< expected number of Gaussian frames flagged per channel
  /// The nominal noise model the correlation test is against: white when nominal_share is 0,
  /// else a Gauss-Markov component with share nominal_share (mu of noise_model.hpp, [0, 0.999])
  /// and correlation time nominal_tau_s [s], seen with the caller's per-frame gains, plus white.
  /// The correlated alternatives add a further Gauss-Markov part to it.
  double nominal_share = 0;
  double nominal_tau_s = 1;
  /// 2 log LR above which the best correlated model whitens the data (AIC: 2 per extra
  /// parameter), > 0; naming it (departs_nominal) takes alpha_correlated.
  double use_correlated_lr = 4;
  /// Likelihood-ratio mode: maximise the ordinary (ML) likelihood instead of REML, with the
  /// fixed effects exactly X (no trend added), and keep the better of the nominal and the
  /// correlated model without a threshold, so that loglik_ml is the profile log-likelihood of
  /// the fixed effects X over the noise family: 2 (loglik_ml(X, C) - loglik_ml(X)) is the
  /// likelihood ratio of columns C with the noise re-estimated under both hypotheses.
  bool profile_ml = false;
  /// Compute NoiseFit::se_tau_s (two more likelihoods per correlated fit); false leaves it 0,
  /// for searches that never report it (the injected ones).
  bool se_tau = true;
  /// Profile mode only: a test that needs the profile log-likelihood only where it reaches this
  /// [log-likelihood] lets the refinement give up once the quadratic top of the likelihood (with
  /// ten times its promised rise as room) stays under it; loglik_ml is then the best model
  /// evaluated, under this value. -inf: always refined to the top.
  double profile_give_up_below = -INFINITY;
};

struct NoiseFit {
  NoiseParams params;             ///< the chosen model (white or correlated; p_out from the flags)
  std::vector<char> outlier;      ///< frames flagged (size n; all 0 when flag_outliers is false)
  double loglik_white = 0;        ///< REML log-likelihood of the white model
  double loglik_correlated = 0;   ///< REML log-likelihood of the best correlated model
  bool correlated = false;        ///< a correlated model is used (the nominal one, or nominal + a further part when that beats the null by use_correlated_lr)
  double loglik_nominal = 0;      ///< REML log-likelihood of the nominal noise model (= white when that is white)
  double s2_nominal = 0;          ///< REML s^2 under the nominal model's structure (its scale is what noise_scale tests)
  double dof_nominal = 0;         ///< its residual degrees of freedom (frames used minus fixed-effect rank)
  bool departs_nominal = false;   ///< the best correlated model is significantly better than the nominal one
  double se_tau_s = 0;            ///< [s] SE of tau from the profile curvature in log tau (0 unless NoiseIdOptions::se_tau)
  double z_outlier = 0;           ///< the flag threshold used
  int n = 0;                      ///< frames used (not flagged)
  double loglik_ml = 0;           ///< ML log-likelihood (scale profiled) under the chosen model, frames used
};

/// The fixed effects leave no spread in the residuals (as many independent columns as frames
/// kept): no noise can be identified on this series with these columns.
struct DegenerateSeries : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// t: frame times [s] (non-decreasing); h: the nominal component's gain per frame (empty: 1);
/// e: residuals; X: fixed-effect columns (n x k, may be empty: a quadratic trend is always
/// added). fixed_skip: frames kept out, given (no flagging). Throws DegenerateSeries when the
/// columns leave no spread.
NoiseFit identify_noise(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                        const Eigen::MatrixXd& X,
                        const NoiseIdOptions& o, const std::vector<char>* fixed_skip = nullptr);

/// The profile noise grid of one series: fixed effects exactly X (no trend), frames skip kept
/// out (empty: none); the null model (the nominal share alone, lambda 0) and each (lambda, tau) of
/// identify_noise's search grid, with the REML and ML log-likelihoods, s^2 profiled. It is what
/// the profile mode of identify_noise searches first, what noise_confidence_set ranks, and what
/// loglik_ml_at gives at a grid model: computed once, it serves all three, bit for bit.
struct NoiseGrid {
  struct Point {
    NoiseParams p;            ///< the model; p.s2 its REML s^2
    double ll = -INFINITY;    ///< REML log-likelihood (-inf: the columns leave no spread)
    double ml = -INFINITY;    ///< ML log-likelihood
    double log_tau = 0;       ///< log of p.tau_s [log s] as the search computes it (the null: 0)
  };
  std::vector<Point> points;  ///< [0] the null model, then tau by tau (ascending), lambda within
};

/// The profile noise grid (NoiseGrid) of residuals e at times t (gains h) with fixed effects X.
/// Options read: the tau range and the nominal component.
NoiseGrid profile_noise_grid(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                             const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>& skip);

/// identify_noise(t, h, e, X, o, &skip) in profile_ml mode (o.profile_ml must be set) with its
/// grid stage read from g, profile_noise_grid(t, h, e, X, o, skip): the same fit, bit for bit.
NoiseFit identify_noise_profile(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                                const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>& skip,
                                const NoiseGrid& g);

/// The indices into g.points of noise_confidence_set at level q (the same models, in its order);
/// empty when no model leaves spread.
std::vector<std::size_t> confidence_indices(const NoiseGrid& g, double q);

/// noise_confidence_set's models ranked from g: those of confidence_indices(g, q), in its order.
/// Throws DegenerateSeries when no model leaves spread.
std::vector<NoiseParams> confidence_set_of(const NoiseGrid& g, double q);

/// A likelihood confidence set for the noise model: the models of identify_noise's search grid
/// (white or nominal, and each (lambda, tau) grid point, the scale s^2 profiled at each) whose
/// REML log-likelihood, fixed effects exactly X (no trend: those of the test the set serves),
/// frames skip kept out (empty: none), lies within q / 2 of the grid's best (profile_noise_grid
/// ranked). With q the chi-square(2) quantile at beta it covers the
/// true (lambda, tau) with probability about 1 - beta (asymptotically; the grid's best is a
/// little below the maximum, so the set is a little larger). Never empty; the most likely first.
std::vector<NoiseParams> noise_confidence_set(const std::vector<double>& t, const std::vector<double>& h,
                                              const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                              const std::vector<char>& skip, double q);

/// The frames of `flags` (identify_noise's outliers on these residuals and columns, kept out of
/// the fit) that stay beyond the flag threshold of their prediction under every noise model of
/// the REML confidence set at q (noise_confidence_set with those frames kept out; each model's
/// scale its REML s^2 with X and the trend, as identify_noise flags): the frames no Gaussian
/// noise model the data allow explains. Why: the flags are decided under one estimate of the
/// noise model, and the share of Gaussian frames beyond a threshold of 3.9 sigma grows fast with
/// an underrated variance (x4 at 10 % in sigma); a Gauss-Markov process whose tau the fit gets
/// wrong (a 25 s process identified as 5 s beside a fitted track) thus gives isolated flags.
/// Under every model of the set, a Gaussian frame is flagged at most as often as under the true
/// model whenever that lies in the set (Berger and Boos's argument, as for the mean effects).
std::vector<char> outliers_beyond_noise_set(const std::vector<double>& t, const std::vector<double>& h,
                                            const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                            const std::vector<char>& flags, double q);

/// The ML log-likelihood, scale profiled, of residuals e with fixed effects exactly X (no trend)
/// under the noise structure of p (its s^2 and outlier part unused), frames skip kept out:
/// identify_noise's loglik_ml at fixed noise parameters (profile_ml mode).
double loglik_ml_at(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                    const Eigen::MatrixXd& X, const NoiseParams& p, const std::vector<char>& skip);

}  // namespace rnav
