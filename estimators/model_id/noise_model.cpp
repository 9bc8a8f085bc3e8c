#include "noise_model.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav {

std::string NoiseParams::kind() const {
  if (lambda <= 0) return "white";
  return lambda > 0.95 ? "gauss_markov" : "gauss_markov_plus_white";
}

namespace {
void check(const NoiseParams& p) {
  if (!(p.s2 > 0) || !(p.lambda >= 0 && p.lambda < 1) || !(p.tau_s > 0) || !(p.p_out >= 0 && p.p_out < 0.5) ||
      !(p.s_out2 >= 0))
    throw std::invalid_argument("NoiseParams out of range (s2 > 0, lambda in [0, 1), tau > 0, p_out in [0, 0.5))");
}
}  // namespace

void whiten(const std::vector<double>& t, const NoiseParams& p, const std::vector<char>& skip,
            Eigen::Ref<Eigen::MatrixXd> M, Eigen::VectorXd* logS) {
  check(p);
  const auto n = static_cast<Eigen::Index>(t.size());
  if (M.rows() != n) throw std::invalid_argument("whiten: rows != number of times");
  if (logS) logS->setZero(n);
  const double q = p.lambda * p.s2, r = (1 - p.lambda) * p.s2;
  Eigen::RowVectorXd g = Eigen::RowVectorXd::Zero(M.cols());  // state estimate, one per column
  double P = q;
  double t_prev = 0;
  bool started = false;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    if (!skip.empty() && skip[ui]) {  // no sample of the noise process: no update
      M.row(i).setZero();
      continue;
    }
    // g-_i = phi g+_(i-1); P-_i = phi^2 P+ + q (1 - phi^2)
    if (started && q > 0) {
      const double phi = std::exp(-(t[ui] - t_prev) / p.tau_s);
      g *= phi;
      P = phi * phi * P + q * (1 - phi * phi);
    }
    const double S = std::max(P + r, 1e-300);
    const Eigen::RowVectorXd nu = M.row(i) - g;
    if (q > 0) {
      const double K = P / S;
      g += K * nu;
      P = (1 - K) * P;
    }
    M.row(i) = nu / std::sqrt(S);
    if (logS) (*logS)(i) = std::log(S);
    t_prev = t[ui];
    started = true;
  }
}

double predictive_loglik(const std::vector<double>& t, const std::vector<double>& e, const NoiseParams& p,
                         const std::vector<char>& score) {
  check(p);
  const double q = p.lambda * p.s2, r = (1 - p.lambda) * p.s2;
  double g = 0, P = q, t_prev = 0, ll = 0;
  bool started = false;
  for (std::size_t i = 0; i < e.size(); ++i) {
    double gm = g, Pm = P;  // predicted to t_i from the last frame that updated the state
    if (started && q > 0) {
      const double phi = std::exp(-(t[i] - t_prev) / p.tau_s);
      gm = phi * g;
      Pm = phi * phi * P + q * (1 - phi * phi);
    }
    const double S = std::max(Pm + r, 1e-300), nu = e[i] - gm;
    const double l_in = -0.5 * (nu * nu / S + std::log(2 * M_PI * S));
    bool outlier = false;
    double l = l_in;
    if (p.p_out > 0) {
      const double So = S + p.s_out2;
      const double l_out = -0.5 * (nu * nu / So + std::log(2 * M_PI * So));
      const double a = std::log1p(-p.p_out) + l_in, b = std::log(p.p_out) + l_out;
      const double m = std::max(a, b);
      l = m + std::log(std::exp(a - m) + std::exp(b - m));
      outlier = b > a;
    }
    if (score.empty() || score[i]) ll += l;
    if (!outlier) {
      const double K = q > 0 ? Pm / S : 0.0;
      g = gm + K * nu;
      P = (1 - K) * Pm;
      t_prev = t[i];
      started = true;
    }
  }
  return ll;
}

}  // namespace rnav
