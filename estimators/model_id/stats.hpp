// Distribution functions and small statistics shared by every diagnosis (no dependency on any
// sensor). Accuracy: relative 1e-12 for the gamma and beta tails over the ranges used here
// (dof <= 1e4, x <= 1e6); the log tails stay finite where the tails underflow a double.
#pragma once

#include <string>
#include <vector>

namespace rnav {

/// Regularized upper incomplete gamma Q(a, x), a > 0, x >= 0.
double gamma_q(double a, double x);
/// log Q(a, x), finite even where Q underflows (x up to ~1e8).
double log_gamma_q(double a, double x);
/// Chi-square survival function P(X > x), k > 0 degrees of freedom.
double chi2_sf(double x, double k);
/// log of chi2_sf.
double log_chi2_sf(double x, double k);
/// log of the Bonferroni-adjusted p of a 2 log LR `lr` with k degrees of freedom, for an entry
/// scanned over `grid` points (1: not scanned) in a family of m_family entries (alpha / m per
/// entry, split over its grid):  log p_adj = log chi2_sf(lr, k) + log grid + log m.  Not
/// capped at 0 (log 1): the caller compares it with log alpha or caps it for display.
double bonferroni_log_p(double lr, double k, double grid, double m_family);
/// Standard normal distribution function Phi(z) = P(Z <= z) = erfc(-z / sqrt 2) / 2.
double normal_cdf(double z);
/// Upper normal quantile: z with P(Z > z) = p, p in (0, 1).
double normal_upper_quantile(double p);
/// Two-sided normal quantile: z with P(|Z| > z) = p, p in (0, 1).
double z_two_sided(double p);
/// Poisson upper tail P(N >= k) for mean lambda >= 0.
double poisson_upper_tail(int k, double lambda);
/// Regularized incomplete beta I_x(a, b), a, b > 0, x in [0, 1].
double beta_inc(double a, double b, double x);
/// Clopper-Pearson interval for k successes in n trials at confidence conf (e.g. 0.95).
struct Interval {
  double lo = 0, hi = 1;
};
Interval clopper_pearson(int k, int n, double conf);
/// A DerSimonian-Laird random-effects pooling of k >= 2 estimates b_i with variances v_i > 0.
struct RandomEffects {
  double fixed_mean = 0;  ///< inverse-variance mean m_w = sum w_i b_i / sum w_i, w_i = 1 / v_i
  double q = 0;           ///< Cochran's Q = sum w_i (b_i - m_w)^2 (chi^2 with k - 1 dof when tau^2 = 0)
  double tau2 = 0;        ///< between-estimate variance, same unit as v (>= 0)
  double mean = 0;        ///< random-effects mean sum w*_i b_i / sum w*_i, w*_i = 1 / (v_i + tau^2)
  double sum_w = 0;       ///< sum w*_i (so the DerSimonian-Laird SE of mean is sum_w^-1/2)
};
/// Pools b (estimates) with var (their variances); sizes equal and >= 2, every var > 0 and
/// finite (throws std::invalid_argument otherwise).
RandomEffects dersimonian_laird(const std::vector<double>& b, const std::vector<double>& var);
/// Median of v (the mean of the two middle values for an even count); v must not be empty.
double median(std::vector<double> v);
/// Median of |v| (robust sigma: 1.4826 * median_abs). Empty v gives 0.
double median_abs(std::vector<double> v);
/// Pearson correlation of x and y (0 when either has no spread).
double pearson(const std::vector<double>& x, const std::vector<double>& y);
/// A number in %.4g for reports (%.1f from 1e5 on: absolute times keep their tenths).
std::string short_num(double x);

}  // namespace rnav
