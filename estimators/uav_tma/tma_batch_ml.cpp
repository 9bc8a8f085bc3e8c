#include "estimators/uav_tma/tma_batch_ml.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rnav::tma {

Row4 batch_bearing_jacobian(const Vec4& theta, double dt_s, const Eigen::Vector2d& p_obs_F) {
  return bearing_jacobian(cv_transition(dt_s) * theta, p_obs_F) * cv_transition(dt_s);
}

BatchMl::BatchMl(const TmaOptions& o, const BatchMlSettings& s) : o_(o), s_(s) {
  if (s.max_trials < 1 || !(s.decrement_tol > 0))
    throw std::invalid_argument("BatchMl: max_trials must be >= 1 and decrement_tol > 0");
}

bool BatchMl::add(const Obs& k, const Vec4& th, const Vec4* held, Sums& s) const {
  const double dn = th[kN] + k.dt_s * th[kVN] - k.on, de = th[kE] + k.dt_s * th[kVE] - k.oe;
  const double D2 = dn * dn + de * de;
  if (!(D2 >= kMinRange_m * kMinRange_m)) return false;
  // Wrapped residual: the angle from the predicted to the measured line of sight.
  const double ry = k.sz * dn - k.cz * de, rx = k.cz * dn + k.sz * de;
  const double r = rx > 0 ? std::atan(ry / rx) : std::atan2(ry, rx);  // atan: cheaper, same angle for rx > 0
  const double w = 1.0 / (o_.add_nav_noise ? k.sb2 + k.sn2 / D2 : k.sb2);
  s.cost += w * r * r;
  if (held) {
    double wh = 1.0 / k.sb2;
    if (o_.add_nav_noise) {
      const double hn = (*held)[kN] + k.dt_s * (*held)[kVN] - k.on, he = (*held)[kE] + k.dt_s * (*held)[kVE] - k.oe;
      wh = 1.0 / (k.sb2 + k.sn2 / (hn * hn + he * he));
    }
    s.cost_held += wh * r * r;
  }
  const double hn = -de / D2, he = dn / D2, t = k.dt_s, t2 = t * t;
  const double nn = w * hn * hn, ne = w * hn * he, ee = w * he * he;
  s.a[0] += nn;
  s.a[1] += ne;
  s.a[2] += ee;
  s.a[3] += t * nn;
  s.a[4] += t * ne;
  s.a[5] += t * ee;
  s.a[6] += t2 * nn;
  s.a[7] += t2 * ne;
  s.a[8] += t2 * ee;
  const double wr = w * r;
  s.b[0] += wr * hn;
  s.b[1] += wr * he;
  s.b[2] += t * wr * hn;
  s.b[3] += t * wr * he;
  return true;
}

BatchMl::Eval BatchMl::finish(const Sums& s, const Vec4& th) const {
  Eval e;
  const Vec4 d = th - m0_;
  const double prior = d.dot(L0_ * d);
  e.cost = s.cost + prior;
  e.cost_held = s.cost_held + prior;
  // J_k^T J_k = [[h h^T, dt h h^T], [dt h h^T, dt^2 h h^T]] summed with the weights 1 / R_k.
  Mat4 S;
  S << s.a[0], s.a[1], s.a[3], s.a[4],
       s.a[1], s.a[2], s.a[4], s.a[5],
       s.a[3], s.a[4], s.a[6], s.a[7],
       s.a[4], s.a[5], s.a[7], s.a[8];
  e.A = L0_ + S;
  e.g = L0_ * (m0_ - th) + Vec4(s.b[0], s.b[1], s.b[2], s.b[3]);
  return e;
}

bool BatchMl::evaluate(const Vec4& th, const Vec4* held, Sums& s, Eval& e) const {
  ++passes_;
  s = Sums{};
  for (const Obs& k : obs_) {
    ++evaluations_;
    if (!add(k, th, held, s)) return false;
  }
  e = finish(s, th);
  s.cost_held = 0;
  return std::isfinite(e.cost) && std::isfinite(e.cost_held) && e.A.allFinite() && e.g.allFinite();
}

double BatchMl::cost(const Vec4& th) const {
  Sums s;
  Eval e;
  return evaluate(th, nullptr, s, e) ? e.cost : std::numeric_limits<double>::infinity();
}

double BatchMl::newton_decrement() const { return g_.dot(A_.ldlt().solve(g_)); }

void BatchMl::solve(int max_trials, double tol) {
  for (int trial = 0; trial < max_trials; ++trial) {
    if (newton_decrement() < tol) return;
    Mat4 M = A_;
    for (int i = 0; i < kDim; ++i) M(i, i) += lambda_ * A_(i, i);
    const Vec4 d = M.ldlt().solve(g_);
    // Decrease of C the quadratic model predicts: 2 g^T d - d^T A d (> 0 for lambda > 0).
    const double predicted = 2 * g_.dot(d) - d.dot(A_ * d);
    const Vec4 th = theta_ + d;
    Sums s;
    Eval e;
    if (d.allFinite() && evaluate(th, &theta_, s, e) && e.cost_held < cost_) {
      const double rho = (cost_ - e.cost_held) / predicted;
      theta_ = th;
      A_ = e.A;
      g_ = e.g;
      cost_ = e.cost;
      sums_ = s;
      lambda_ *= std::max(1.0 / 3, 1 - std::pow(2 * std::min(rho, 1.0) - 1, 3));
      lambda_ = std::max(lambda_, 1e-12);
      nu_ = 2;
    } else {
      lambda_ = std::min(lambda_ * nu_, 1e12);
      nu_ *= 2;
    }
  }
}

void BatchMl::refine(int max_trials, double tol) {
  if (init_) solve(max_trials, tol);
}

void BatchMl::predict_to(double t_s) {
  if (!init_) return;
  if (t_s < t_) throw std::invalid_argument("BatchMl: time went backwards");
  t_ = t_s;
}

Gaussian BatchMl::estimate() const {
  Gaussian g;
  const Mat4 F = cv_transition(t_ - t0_);
  g.x = F * theta_;
  const Mat4 S = A_.ldlt().solve(Mat4::Identity());
  g.P = F * S * F.transpose();
  g.P = 0.5 * (g.P + g.P.transpose());
  return g;
}

double BatchMl::process(const BearingMeas& z) {
  if (!init_) {
    // The filters' prior, built by the filter itself (one definition).
    CartesianEkf prior(o_, o_.range_prior_m, o_.range_sigma_m);
    prior.process(z);
    const Gaussian p = prior.estimate();
    m0_ = p.x;
    L0_ = p.P.ldlt().solve(Mat4::Identity());
    L0_ = 0.5 * (L0_ + L0_.transpose());
    theta_ = m0_;
    t0_ = t_ = z.t_s;
    obs_.clear();
    sums_ = Sums{};
    const Eval e = finish(sums_, theta_);
    A_ = e.A;
    g_ = e.g;
    cost_ = e.cost;
    init_ = true;
    return 0;
  }
  if (z.t_s < t_) throw std::invalid_argument("BatchMl: time went backwards");
  t_ = z.t_s;
  const double nis = bearing_nis(estimate(), z, o_.add_nav_noise);
  Obs k;
  k.dt_s = z.t_s - t0_;
  k.on = z.p_obs_F.x();
  k.oe = z.p_obs_F.y();
  k.sz = std::sin(z.bearing_rad);
  k.cz = std::cos(z.bearing_rad);
  k.sb2 = z.sigma_rad * z.sigma_rad;
  k.sn2 = z.sigma_nav_m * z.sigma_nav_m;
  if (!(k.sb2 > 0)) throw std::invalid_argument("BatchMl: bearing sigma must be > 0");
  // The new bearing at the current solution: A, g, C updated in O(1).
  Sums s = sums_;
  ++evaluations_;
  if (!add(k, theta_, nullptr, s))
    throw std::runtime_error("BatchMl: a bearing taken at the estimated object position (range 0)");
  obs_.push_back(k);
  sums_ = s;
  const Eval e = finish(sums_, theta_);
  A_ = e.A;
  g_ = e.g;
  cost_ = e.cost;
  solve(s_.max_trials, s_.decrement_tol);
  return nis;
}

}  // namespace rnav::tma
