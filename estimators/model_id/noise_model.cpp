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
  if (!(p.s2 > 0) || !(p.lambda >= 0 && p.lambda < 1) || !(p.tau_s > 0) || !(p.nom_share >= 0 && p.nom_share < 1) ||
      !(p.nom_tau_s > 0) || !(p.p_out >= 0 && p.p_out < 0.5) || !(p.s_out2 >= 0))
    throw std::invalid_argument(
        "NoiseParams out of range (s2 > 0, lambda and nom_share in [0, 1), tau and nom_tau > 0, p_out in [0, 0.5))");
}
}  // namespace

NoiseFilter::NoiseFilter(const NoiseParams& p, const std::vector<double>& gain, Eigen::Index k)
    : q0_(p.nom_share * p.s2),
      q_((1 - p.nom_share) * p.lambda * p.s2),
      r_((1 - p.nom_share) * (1 - p.lambda) * p.s2),
      tau0_(p.nom_tau_s),
      tau_(p.tau_s),
      gain_(&gain),
      x_(Eigen::Matrix<double, 2, Eigen::Dynamic>::Zero(2, k)) {
  check(p);
  P_ << q0_, 0, 0, q_;  // stationary start
}

double NoiseFilter::predict(std::size_t i, double t) {
  if (!gain_->empty() && i >= gain_->size()) throw std::invalid_argument("NoiseFilter: frame index beyond the gain profile");
  H_ << (gain_->empty() ? 1.0 : (*gain_)[i]), 1.0;
  if (started_) {
    // x- = Phi x+, P- = Phi P+ Phi + diag(q0 (1 - phi0^2), q (1 - phi^2))
    const double dt = t - t_prev_;
    const double f0 = q0_ > 0 ? std::exp(-dt / tau0_) : 0.0, f = q_ > 0 ? std::exp(-dt / tau_) : 0.0;
    x_.row(0) *= f0;
    x_.row(1) *= f;
    P_(0, 0) = f0 * f0 * P_(0, 0) + q0_ * (1 - f0 * f0);
    P_(1, 1) = f * f * P_(1, 1) + q_ * (1 - f * f);
    P_(0, 1) = P_(1, 0) = f0 * f * P_(0, 1);
  }
  t_prev_ = t;
  S_ = std::max(H_ * P_ * H_.transpose() + r_, 1e-300);
  return S_;
}

Eigen::RowVectorXd NoiseFilter::mean() const { return H_ * x_; }

void NoiseFilter::update(const Eigen::RowVectorXd& nu) {
  // K = P- H' / S; x+ = x- + K nu; P+ = (I - K H) P-, symmetrised
  const Eigen::Vector2d K = P_ * H_.transpose() / S_;
  x_ += K * nu;
  P_ = (Eigen::Matrix2d::Identity() - K * H_) * P_;
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  started_ = true;
}

void whiten(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p,
            const std::vector<char>& skip, Eigen::Ref<Eigen::MatrixXd> M, Eigen::VectorXd* logS) {
  const auto n = static_cast<Eigen::Index>(t.size());
  if (M.rows() != n) throw std::invalid_argument("whiten: rows != number of times");
  if (!h.empty() && h.size() != t.size()) throw std::invalid_argument("whiten: gains != number of times");
  if (logS) logS->setZero(n);
  NoiseFilter f(p, h, M.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    if (!skip.empty() && skip[ui]) {  // no sample of the noise process: no update
      M.row(i).setZero();
      continue;
    }
    const double S = f.predict(ui, t[ui]);
    const Eigen::RowVectorXd nu = M.row(i) - f.mean();
    f.update(nu);
    M.row(i) = nu / std::sqrt(S);
    if (logS) (*logS)(i) = std::log(S);
  }
}

double predictive_loglik(const std::vector<double>& t, const std::vector<double>& h, const std::vector<double>& e,
                         const NoiseParams& p, const std::vector<char>& score) {
  if (!h.empty() && h.size() != t.size()) throw std::invalid_argument("predictive_loglik: gains != number of times");
  if (e.size() != t.size()) throw std::invalid_argument("predictive_loglik: residuals != number of times");
  NoiseFilter f(p, h, 1);
  double ll = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    // predicted to t_i from the last frame that updated the state (an outlier does not)
    NoiseFilter trial = f;
    const double S = trial.predict(i, t[i]), nu = e[i] - trial.mean()(0);
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
      trial.update(Eigen::RowVectorXd::Constant(1, nu));
      f = trial;
    }
  }
  return ll;
}

}  // namespace rnav
