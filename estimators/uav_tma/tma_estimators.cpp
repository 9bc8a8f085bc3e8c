#include "estimators/uav_tma/tma_estimators.hpp"

#include "common/physics/frames.hpp"
#include "estimators/uav_tma/tma_batch_ml.hpp"
#include "estimators/uav_tma/tma_particle.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav::tma {

namespace {
double meas_variance(const TmaOptions& o, const BearingMeas& z, double D) {
  return o.add_nav_noise ? bearing_variance(z.sigma_rad, z.sigma_nav_m, D) : z.sigma_rad * z.sigma_rad;
}
}  // namespace

double bearing_nis(const Gaussian& g, const BearingMeas& z, bool add_nav_noise) {
  const double D = range(g.x, z.p_obs_F);
  const double R = add_nav_noise ? bearing_variance(z.sigma_rad, z.sigma_nav_m, D) : z.sigma_rad * z.sigma_rad;
  const Row4 H = bearing_jacobian(g.x, z.p_obs_F);
  const double nu = wrap_pi(z.bearing_rad - bearing(g.x, z.p_obs_F));
  return nu * nu / ((H * g.P * H.transpose())(0, 0) + R);
}

CartesianEkf::CartesianEkf(const TmaOptions& o, double range_m, double range_sigma_m)
    : o_(o), r0_(range_m), sr_(range_sigma_m) {
  if (!(range_m > 0) || !(range_sigma_m > 0))
    throw std::invalid_argument("CartesianEkf: range prior and its sigma must be > 0");
}

void CartesianEkf::predict_to(double t_s) {
  if (!init_) return;
  const double dt = t_s - t_s_;
  if (dt < 0) throw std::invalid_argument("CartesianEkf: time went backwards");
  if (dt > 0) predict(g_, cv_transition(dt), cv_process_noise(o_.q_m2ps3, dt));
  t_s_ = t_s;
}

double CartesianEkf::process(const BearingMeas& z) {
  if (!init_) {
    // Position on the first bearing at the prior range: radial sigma_r, cross-range r0 sigma_b.
    const Eigen::Vector2d u(std::cos(z.bearing_rad), std::sin(z.bearing_rad)), c(-u.y(), u.x());
    const double Rb = meas_variance(o_, z, r0_);
    g_.x.setZero();
    g_.x.head<2>() = z.p_obs_F + r0_ * u;
    g_.P.setZero();
    g_.P.topLeftCorner<2, 2>() = sr_ * sr_ * u * u.transpose() + r0_ * r0_ * Rb * c * c.transpose();
    g_.P(kVN, kVN) = g_.P(kVE, kVE) = o_.vel_sigma_mps * o_.vel_sigma_mps;
    t_s_ = z.t_s;
    init_ = true;
    last_log_lik_ = 0;
    return 0;
  }
  predict_to(z.t_s);                                   // X_bar = Phi X_hat
  const double A = bearing(g_.x, z.p_obs_F);           // A_bar
  const double D = range(g_.x, z.p_obs_F);             // D_bar
  const double nu = wrap_pi(z.bearing_rad - A);        // wrapped innovation
  const ScalarUpdate u = update(g_, nu, bearing_jacobian(g_.x, z.p_obs_F), meas_variance(o_, z, D));
  last_log_lik_ = u.log_lik;
  return u.nis;
}

RangeParameterisedEkf::RangeParameterisedEkf(const TmaOptions& o) : o_(o) {
  const int n = static_cast<int>(o.bank_size);
  const double rho = std::pow(o.bank_max_m / o.bank_min_m, 1.0 / (n - 1));
  // sigma_i / r_i = 2 (rho - 1) / (sqrt(12) (rho + 1)): neighbouring priors overlap (Peach 1995).
  const double cv = 2 * (rho - 1) / (std::sqrt(12.0) * (rho + 1));
  for (int i = 0; i < n; ++i) {
    const double r = o.bank_min_m * std::pow(rho, i);
    bank_.emplace_back(o, r, cv * r);
  }
  w_.assign(bank_.size(), 1.0 / bank_.size());
}

void RangeParameterisedEkf::predict_to(double t_s) {
  for (auto& f : bank_) f.predict_to(t_s);
}

Gaussian RangeParameterisedEkf::estimate() const {
  Gaussian m;
  m.x.setZero();
  for (std::size_t i = 0; i < bank_.size(); ++i) m.x += w_[i] * bank_[i].estimate().x;
  m.P.setZero();
  for (std::size_t i = 0; i < bank_.size(); ++i) {
    const Gaussian g = bank_[i].estimate();
    const Vec4 d = g.x - m.x;
    m.P += w_[i] * (g.P + d * d.transpose());
  }
  m.P = 0.5 * (m.P + m.P.transpose());
  return m;
}

double RangeParameterisedEkf::process(const BearingMeas& z) {
  if (!init_) {
    for (auto& f : bank_) f.process(z);
    init_ = true;
    return 0;
  }
  predict_to(z.t_s);
  const double nis = bearing_nis(estimate(), z, o_.add_nav_noise);
  // w_i <- w_i N(nu_i; 0, S_i), normalised in the log domain.
  std::vector<double> lw(bank_.size());
  double mx = -INFINITY;
  for (std::size_t i = 0; i < bank_.size(); ++i) {
    bank_[i].process(z);
    lw[i] = std::log(w_[i]) + bank_[i].last_log_lik();
    mx = std::max(mx, lw[i]);
  }
  double sum = 0;
  for (std::size_t i = 0; i < bank_.size(); ++i) sum += (w_[i] = std::exp(lw[i] - mx));
  for (auto& w : w_) w /= sum;
  // Drop members whose weight can no longer matter (deterministic, keeps the bank cheap).
  for (std::size_t i = bank_.size(); i-- > 0;)
    if (w_[i] < 1e-12 && bank_.size() > 1) {
      bank_.erase(bank_.begin() + static_cast<long>(i));
      w_.erase(w_.begin() + static_cast<long>(i));
    }
  sum = 0;
  for (double w : w_) sum += w;
  for (auto& w : w_) w /= sum;
  return nis;
}

std::vector<std::unique_ptr<TmaEstimator>> make_estimators(const TmaOptions& o, std::uint64_t seed,
                                                           std::uint64_t realization) {
  std::vector<std::unique_ptr<TmaEstimator>> v;
  for (const std::string& name : o.estimators) {
    if (name == "ekf") v.push_back(std::make_unique<CartesianEkf>(o, o.range_prior_m, o.range_sigma_m));
    else if (name == "rpekf") v.push_back(std::make_unique<RangeParameterisedEkf>(o));
    else if (name == "ml") v.push_back(std::make_unique<BatchMl>(o));
    else if (name == "pf") v.push_back(std::make_unique<ParticleFilter>(o, seed, realization));
    else throw std::invalid_argument("make_estimators: unknown estimator '" + name + "' (tma.estimators)");
  }
  return v;
}

}  // namespace rnav::tma
