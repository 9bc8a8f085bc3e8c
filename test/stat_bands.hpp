// Acceptance bands for the statistical (Monte Carlo) unit tests.
//
// Every Monte Carlo test uses fixed seeds, so it is deterministic; the bands below are chosen so
// that a correct implementation would pass for ~99.9 % of all seeds (per assertion), while a
// wrong variance / mean / correlation (by more than a few standard errors) fails.
#pragma once

#include <cmath>
#include <vector>

namespace rnav_test {

/// Two-sided 99.9 % standard normal quantile z_{0.9995}.
constexpr double kZ999 = 3.2905267314918945;

/// Chi-square quantile by the Wilson-Hilferty approximation: for X ~ chi2(k),
/// (X/k)^(1/3) is approximately N(1 - 2/(9k), 2/(9k)), so
///   x_p = k (1 - 2/(9k) + z_p sqrt(2/(9k)))^3.
/// Its relative error in the quantile is far below 1e-3 for k in the hundreds and above, which
/// is all we use (k = N or N-1 with N of a few thousand).
inline double chi2_quantile_wh(double k, double z) {
  const double c = 2.0 / (9.0 * k);
  const double b = 1.0 - c + z * std::sqrt(c);
  return k * b * b * b;
}

/// Band [lo, hi] for the ratio s^2 / sigma^2 of an estimated variance s^2 with `dof` degrees of
/// freedom to the true variance: dof s^2 / sigma^2 ~ chi2(dof), two-sided 99.9 %.
struct Band {
  double lo, hi;
  bool contains(double x) const { return lo <= x && x <= hi; }
};
inline Band variance_ratio_band(double dof, double z = kZ999) {
  return {chi2_quantile_wh(dof, -z) / dof, chi2_quantile_wh(dof, z) / dof};
}

inline double mean(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}
/// Sample variance with n - 1 (n - 1 degrees of freedom).
inline double sample_variance(const std::vector<double>& x) {
  const double m = mean(x);
  double s = 0;
  for (double v : x) s += (v - m) * (v - m);
  return s / static_cast<double>(x.size() - 1);
}
/// Mean square about a known mean mu (n degrees of freedom).
inline double mean_square_about(const std::vector<double>& x, double mu) {
  double s = 0;
  for (double v : x) s += (v - mu) * (v - mu);
  return s / static_cast<double>(x.size());
}
/// Sample correlation coefficient.
inline double correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const double mx = mean(x), my = mean(y);
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxy / std::sqrt(sxx * syy);
}

}  // namespace rnav_test
