#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rnav {

namespace {
// Series for log P(a, x) (x < a + 1).
double log_gamma_p_series(double a, double x) {
  double ap = a, sum = 1.0 / a, del = sum;
  for (int n = 0; n < 100000; ++n) {
    ap += 1;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * 1e-16) break;
  }
  return std::log(sum) - x + a * std::log(x) - std::lgamma(a);
}
// Continued fraction for log Q(a, x) (x >= a + 1), modified Lentz.
double log_gamma_q_cf(double a, double x) {
  double b = x + 1 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return -x + a * std::log(x) - std::lgamma(a) + std::log(h);
}
}  // namespace

double log_gamma_q(double a, double x) {
  if (!(a > 0) || !(x >= 0)) throw std::invalid_argument("log_gamma_q: needs a > 0 and x >= 0");
  if (x == 0) return 0.0;
  if (x < a + 1) return std::log1p(-std::exp(log_gamma_p_series(a, x)));
  return log_gamma_q_cf(a, x);
}

double gamma_q(double a, double x) { return std::exp(log_gamma_q(a, x)); }
double chi2_sf(double x, double k) { return x <= 0 ? 1.0 : gamma_q(k / 2, x / 2); }
double log_chi2_sf(double x, double k) { return x <= 0 ? 0.0 : log_gamma_q(k / 2, x / 2); }

double bonferroni_log_p(double lr, double k, double grid, double m_family) {
  return log_chi2_sf(lr, k) + std::log(grid) + std::log(m_family);
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normal_upper_quantile(double p) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("normal_upper_quantile: p must be in (0, 1)");
  // Bisection on erfc (monotone); 200 halvings of [-40, 40] reach double precision.
  double lo = -40, hi = 40;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double z_two_sided(double p) { return normal_upper_quantile(p / 2); }

double poisson_upper_tail(int k, double lambda) {
  if (k <= 0) return 1.0;
  // 1 - P(N <= k - 1) = P(k, lambda) regularized lower gamma.
  return lambda <= 0 ? 0.0 : 1.0 - gamma_q(static_cast<double>(k), lambda);
}

double beta_inc(double a, double b, double x) {
  if (!(a > 0 && b > 0 && x >= 0 && x <= 1)) throw std::invalid_argument("beta_inc: needs a, b > 0 and x in [0, 1]");
  if (x == 0 || x == 1) return x;
  const double lbt = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  // Continued fraction (modified Lentz), on the side where it converges fast.
  auto cf = [](double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1, d = 1 - (a + b) * x / (a + 1);
    if (std::abs(d) < tiny) d = tiny;
    d = 1 / d;
    double h = d;
    for (int m = 1; m < 100000; ++m) {
      const double m2 = 2.0 * m;
      double aa = m * (b - m) * x / ((a - 1 + m2) * (a + m2));
      d = 1 + aa * d;
      if (std::abs(d) < tiny) d = tiny;
      c = 1 + aa / c;
      if (std::abs(c) < tiny) c = tiny;
      d = 1 / d;
      h *= d * c;
      aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1 + m2));
      d = 1 + aa * d;
      if (std::abs(d) < tiny) d = tiny;
      c = 1 + aa / c;
      if (std::abs(c) < tiny) c = tiny;
      d = 1 / d;
      const double del = d * c;
      h *= del;
      if (std::abs(del - 1) < 1e-16) break;
    }
    return h;
  };
  if (x < (a + 1) / (a + b + 2)) return std::exp(lbt) * cf(a, b, x) / a;
  return 1 - std::exp(lbt) * cf(b, a, 1 - x) / b;
}

Interval clopper_pearson(int k, int n, double conf) {
  if (n <= 0 || k < 0 || k > n || !(conf > 0 && conf < 1))
    throw std::invalid_argument("clopper_pearson: needs 0 <= k <= n, n > 0, conf in (0, 1)");
  const double a = (1 - conf) / 2;
  // Bounds: I_lo(k, n - k + 1) = a and I_hi(k + 1, n - k) = 1 - a, by bisection.
  auto solve = [](double aa, double bb, double target) {
    double lo = 0, hi = 1;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (beta_inc(aa, bb, mid) < target ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  Interval iv;
  iv.lo = k == 0 ? 0.0 : solve(k, n - k + 1, a);
  iv.hi = k == n ? 1.0 : solve(k + 1, n - k, 1 - a);
  return iv;
}

RandomEffects dersimonian_laird(const std::vector<double>& b, const std::vector<double>& var) {
  if (b.size() != var.size() || b.size() < 2)
    throw std::invalid_argument("dersimonian_laird: needs two or more estimates with one variance each");
  for (double v : var)
    if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument("dersimonian_laird: a variance is not positive and finite");
  // w_i = 1 / v_i, m_w = sum w_i b_i / sum w_i, Q = sum w_i (b_i - m_w)^2,
  //   tau^2 = max(0, (Q - (k - 1)) / (sum w - sum w^2 / sum w))
  double sw = 0, sw2 = 0, swb = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double w = 1 / var[i];
    sw += w, sw2 += w * w, swb += w * b[i];
  }
  RandomEffects r;
  r.fixed_mean = swb / sw;
  for (std::size_t i = 0; i < b.size(); ++i) r.q += (b[i] - r.fixed_mean) * (b[i] - r.fixed_mean) / var[i];
  const double k = static_cast<double>(b.size());
  r.tau2 = std::max(0.0, (r.q - (k - 1)) / (sw - sw2 / sw));
  // w*_i = 1 / (v_i + tau^2), mean = sum w*_i b_i / sum w*_i
  double swsb = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double w = 1 / (var[i] + r.tau2);
    r.sum_w += w, swsb += w * b[i];
  }
  r.mean = swsb / r.sum_w;
  return r;
}

double median(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("median of no values");
  const std::size_t n = v.size(), m = n / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  const double hi = v[m];
  if (n % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)));
}

double median_abs(std::vector<double> v) {
  if (v.empty()) return 0.0;
  for (auto& x : v) x = std::abs(x);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  if (x.size() < 2 || y.size() != x.size()) return 0.0;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

std::string short_num(double x) {
  char b[64];
  std::snprintf(b, sizeof b, std::abs(x) >= 1e5 && std::abs(x) < 1e15 ? "%.1f" : "%.4g", x);
  return b;
}

}  // namespace rnav
