#include "estimators/uav_tma/tma_particle.hpp"

#include "common/physics/bearing.hpp"
#include "common/physics/frames.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rnav::tma {

namespace {
constexpr int kStateDim = kDim;

double meas_variance(const TmaOptions& o, const BearingMeas& z, double D) {
  return o.add_nav_noise ? bearing_variance(z.sigma_rad, z.sigma_nav_m, D) : z.sigma_rad * z.sigma_rad;
}

/// An L with L L^T = S for a symmetric positive semi-definite S (LDL^T with the
/// negative rounding of zero pivots clipped): works when S is singular, as a cloud of identical
/// particles' covariance is.
Mat4 psd_sqrt(const Mat4& S) {
  Eigen::LLT<Mat4> llt(S);
  if (llt.info() == Eigen::Success) return llt.matrixL();
  Eigen::LDLT<Mat4> ldlt(S);
  const Vec4 d = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
  Mat4 L = ldlt.matrixL();
  L = ldlt.transpositionsP().transpose() * L;
  return L * d.asDiagonal();
}
}  // namespace

double silverman_bandwidth(long m, int d) {
  if (m < 1 || d < 1) throw std::invalid_argument("silverman_bandwidth: m and d must be >= 1");
  return std::pow(4.0 / (static_cast<double>(m) * (d + 2)), 1.0 / (d + 4));
}

std::vector<int> systematic_resample(const std::vector<double>& w, double u) {
  if (!(u >= 0 && u < 1)) throw std::invalid_argument("systematic_resample: u must be in [0, 1)");
  const int m = static_cast<int>(w.size());
  std::vector<int> idx;
  idx.reserve(w.size());
  // Pointer k at (k + u) / m; particle j covers the cumulative weight interval [c_{j-1}, c_j).
  double c = 0;
  int j = 0;
  for (int k = 0; k < m; ++k) {
    const double pos = (k + u) / m;
    while (j < m - 1 && c + w[j] <= pos) c += w[j++];
    idx.push_back(j);
  }
  return idx;
}

ParticleFilter::ParticleFilter(const TmaOptions& o, std::uint64_t seed, std::uint64_t realization,
                               const ParticleSettings& s)
    : o_(o), s_(s), rng_(seed, realization, Stream::kTmaParticle) {
  if (o.pf_particles < 2) throw std::invalid_argument("ParticleFilter: tma.pf_particles must be >= 2");
  if (!(o.bank_min_m > 0 && o.bank_min_m < o.bank_max_m))
    throw std::invalid_argument("ParticleFilter: need 0 < tma.bank_min_m < tma.bank_max_m");
  if (!(s.resample_fraction > 0 && s.resample_fraction <= 1))
    throw std::invalid_argument("ParticleFilter: resample_fraction must be in (0, 1]");
  if (!(s.kernel_scale > 0 && s.kernel_scale * silverman_bandwidth(o.pf_particles, kStateDim) < 1))
    throw std::invalid_argument("ParticleFilter: kernel_scale must be > 0 with bandwidth h < 1");
}

void ParticleFilter::initialise(const BearingMeas& z) {
  const long m = o_.pf_particles;
  x_.assign(static_cast<std::size_t>(m), Vec4::Zero());
  w_.assign(static_cast<std::size_t>(m), 1.0 / static_cast<double>(m));
  const double log_span = std::log(o_.bank_max_m / o_.bank_min_m);
  for (Vec4& x : x_) {
    // r ~ log-uniform on [bank_min, bank_max]; b ~ N(b0, R0(r)); v ~ N(0, s_v^2 I).
    const double r = o_.bank_min_m * std::exp(log_span * rng_.uniform());
    const double b = z.bearing_rad + std::sqrt(meas_variance(o_, z, r)) * rng_.normal();
    x(kN) = z.p_obs_F.x() + r * std::cos(b);
    x(kE) = z.p_obs_F.y() + r * std::sin(b);
    x(kVN) = o_.vel_sigma_mps * rng_.normal();
    x(kVE) = o_.vel_sigma_mps * rng_.normal();
  }
  t_s_ = z.t_s;
  init_ = true;
  refresh_estimate();
}

void ParticleFilter::predict_to(double t_s) {
  if (!init_) return;
  const double dt = t_s - t_s_;
  if (dt < 0) throw std::invalid_argument("ParticleFilter: time went backwards");
  if (dt == 0) return;
  // x <- F x + L_Q n  (no noise when q = 0).
  const Mat4 F = cv_transition(dt);
  const Mat4 Q = cv_process_noise(o_.q_m2ps3, dt);
  if (o_.q_m2ps3 > 0) {
    const Mat4 L = psd_sqrt(Q);
    for (Vec4& x : x_) {
      Vec4 n;
      for (int k = 0; k < kStateDim; ++k) n(k) = rng_.normal();
      x = F * x + L * n;
    }
  } else {
    for (Vec4& x : x_) x = F * x;
  }
  // The output's moments move with the particles: xbar <- F xbar (exact), S <- F S F^T + Q (exact
  // for q = 0; with q > 0 the expectation over the noise drawn, which the next update's
  // refresh_estimate replaces by the cloud's own moments).
  est_.x = F * est_.x;
  est_.P = F * est_.P * F.transpose() + Q;
  est_.P = 0.5 * (est_.P + est_.P.transpose());
  t_s_ = t_s;
}

void ParticleFilter::update(const BearingMeas& z) {
  // log w_i += -nu_i^2 / (2 R_i) - log(R_i) / 2, normalised in the log domain.
  std::vector<double> lw(x_.size());
  const double sb2 = z.sigma_rad * z.sigma_rad, sn2 = z.sigma_nav_m * z.sigma_nav_m;
  double mx = -INFINITY;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const double dn = x_[i](kN) - z.p_obs_F.x(), de = x_[i](kE) - z.p_obs_F.y();
    // R = sigma_b^2 + sigma_nav^2 / D^2 (bearing_variance) from D^2, without the square root.
    const double R = o_.add_nav_noise ? sb2 + sn2 / (dn * dn + de * de) : sb2;
    const double nu = wrap_pi(z.bearing_rad - bearing_rad(Eigen::Vector2d(dn, de)));
    lw[i] = std::log(w_[i]) - 0.5 * nu * nu / R - 0.5 * std::log(R);
    mx = std::max(mx, lw[i]);
  }
  if (!std::isfinite(mx))
    throw std::runtime_error("ParticleFilter: no particle has a finite likelihood for the bearing at t = " +
                             std::to_string(z.t_s) + " s");
  double sum = 0;
  for (std::size_t i = 0; i < x_.size(); ++i) sum += (w_[i] = std::exp(lw[i] - mx));
  for (double& w : w_) w /= sum;
}

double ParticleFilter::effective_sample_size() const {
  double s2 = 0;
  for (double w : w_) s2 += w * w;
  return 1.0 / s2;
}

void liu_west_regularise(std::vector<Vec4>& x, const Vec4& xbar, const Mat4& S, double h, Rng& rng) {
  if (!(h > 0 && h < 1)) throw std::invalid_argument("liu_west_regularise: h must be in (0, 1)");
  const Mat4 L = psd_sqrt(S);
  const double a = std::sqrt(1 - h * h);
  for (Vec4& xi : x) {
    // x_i <- a x_i + (1 - a) xbar + h L_S n_i.
    Vec4 n;
    for (int k = 0; k < kStateDim; ++k) n(k) = rng.normal();
    xi = a * xi + (1 - a) * xbar + h * (L * n);
  }
}

void ParticleFilter::resample() {
  // The weighted cloud's mean and covariance (est_, refreshed after the update) are what the
  // shrinkage kernel keeps.
  const double h = s_.kernel_scale * silverman_bandwidth(static_cast<long>(x_.size()), kStateDim);
  const std::vector<int> idx = systematic_resample(w_, rng_.uniform());
  std::vector<Vec4> y(x_.size());
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = x_[static_cast<std::size_t>(idx[i])];
  liu_west_regularise(y, est_.x, est_.P, h, rng_);
  x_.swap(y);
  std::fill(w_.begin(), w_.end(), 1.0 / static_cast<double>(w_.size()));
  ++resamples_;
}

void ParticleFilter::refresh_estimate() {
  // xbar = sum w_i x_i,  S = sum w_i (x_i - xbar)(x_i - xbar)^T (upper triangle summed, mirrored).
  Vec4 m = Vec4::Zero();
  for (std::size_t i = 0; i < x_.size(); ++i) m += w_[i] * x_[i];
  Mat4 P = Mat4::Zero();
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const Vec4 d = x_[i] - m;
    for (int c = 0; c < kStateDim; ++c)
      for (int r = 0; r <= c; ++r) P(r, c) += w_[i] * d(r) * d(c);
  }
  est_.x = m;
  est_.P = P.selfadjointView<Eigen::Upper>();
  if (!est_.x.allFinite() || !est_.P.allFinite())
    throw std::runtime_error("ParticleFilter: estimate is not finite at t = " + std::to_string(t_s_) + " s");
}

double ParticleFilter::process(const BearingMeas& z) {
  if (!init_) {
    initialise(z);
    return 0;
  }
  predict_to(z.t_s);
  const double nis = bearing_nis(est_, z, o_.add_nav_noise);
  update(z);
  refresh_estimate();
  if (effective_sample_size() < s_.resample_fraction * static_cast<double>(x_.size())) {
    resample();
    refresh_estimate();
  }
  return nis;
}

}  // namespace rnav::tma
