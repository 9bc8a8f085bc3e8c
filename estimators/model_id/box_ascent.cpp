// A trust-region Newton ascent in a 2-D box from batched stencils (box_ascent.hpp).
#include "estimators/model_id/box_ascent.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav {

namespace {

// How the stencil samples one coordinate at a point: both sides (central differences), or two
// points on one side at a face of the box.
enum class Side { kCentral, kForward, kBackward };

struct Stencil {
  double h;  // its step
  Side side[2];
  // the 5 points: (first, second) along coordinate 0, the same along 1, then the mixed point
  std::vector<Eigen::Vector2d> points;
};

Stencil stencil_at(const Eigen::Vector2d& c, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double h) {
  Stencil s;
  s.h = h;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d e = Eigen::Vector2d::Zero();
    e(k) = h;
    if (c(k) - h >= lo(k) && c(k) + h <= hi(k)) {
      s.side[k] = Side::kCentral;
      s.points.push_back(c + e), s.points.push_back(c - e);
    } else if (c(k) + h > hi(k)) {
      s.side[k] = Side::kBackward;
      s.points.push_back(c - e), s.points.push_back(c - 2 * e);
    } else {
      s.side[k] = Side::kForward;
      s.points.push_back(c + e), s.points.push_back(c + 2 * e);
    }
  }
  // the mixed point: one step along each coordinate, on the side its first point lies
  s.points.push_back(Eigen::Vector2d(s.points[0](0), s.points[2](1)));
  return s;
}

// The gradient and Hessian at the stencil's centre (value f0) from its 5 values v.
//   central:  g = (f(+h) - f(-h)) / 2h,            H = (f(+h) - 2 f0 + f(-h)) / h^2
//   forward:  g = (-3 f0 + 4 f(+h) - f(+2h)) / 2h, H = (f0 - 2 f(+h) + f(+2h)) / h^2
//   backward: g = (3 f0 - 4 f(-h) + f(-2h)) / 2h,  H = (f0 - 2 f(-h) + f(-2h)) / h^2
//   mixed:    H01 = (f(a, b) - f(a, 0) - f(0, b) + f0) / (a b), a, b = +-h the first points' offsets
void derivatives(const Stencil& s, double f0, const std::vector<double>& v, Eigen::Vector2d& g, Eigen::Matrix2d& H) {
  const double h = s.h;
  double sign[2] = {1, 1};
  for (int k = 0; k < 2; ++k) {
    const double f1 = v[2 * k], f2 = v[2 * k + 1];
    switch (s.side[k]) {
      case Side::kCentral: g(k) = (f1 - f2) / (2 * h), H(k, k) = (f1 - 2 * f0 + f2) / (h * h), sign[k] = 1; break;
      case Side::kForward: g(k) = (-3 * f0 + 4 * f1 - f2) / (2 * h), H(k, k) = (f0 - 2 * f1 + f2) / (h * h), sign[k] = 1; break;
      case Side::kBackward: g(k) = (3 * f0 - 4 * f1 + f2) / (2 * h), H(k, k) = (f0 - 2 * f1 + f2) / (h * h), sign[k] = -1; break;
    }
  }
  H(0, 1) = H(1, 0) = (v[4] - v[0] - v[2] + f0) / (sign[0] * sign[1] * h * h);
}

// The step s maximising g's + s'Hs / 2 over |s| <= delta: the Newton step when H is negative
// definite and the step fits; else s(mu) = (mu I - H)^-1 g with mu > max(0, largest eigenvalue)
// such that |s(mu)| = delta (bisection; |s(mu)| falls as mu grows), plus a move along the
// largest eigenvalue's vector when even mu at that bound leaves |s| short (the "hard case").
Eigen::Vector2d trust_step(const Eigen::Vector2d& g, const Eigen::Matrix2d& H, double delta) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(H);
  const Eigen::Vector2d ev = es.eigenvalues();  // ascending
  const Eigen::Matrix2d Q = es.eigenvectors();
  const Eigen::Vector2d qg = Q.transpose() * g;
  auto step = [&](double mu) {
    return Eigen::Vector2d(Q * Eigen::Vector2d(qg(0) / (mu - ev(0)), qg(1) / (mu - ev(1))));
  };
  if (ev(1) < 0) {
    const Eigen::Vector2d s = step(0);
    if (s.norm() <= delta) return s;
  }
  const double mu_lo = std::max(0.0, ev(1)), mu_hi = mu_lo + g.norm() / delta + 1e-300;
  const double tiny = 1e-12 * std::max({1.0, std::abs(ev(0)), std::abs(ev(1))});
  const Eigen::Vector2d s_lo = step(mu_lo + tiny);
  if (!(s_lo.norm() >= delta)) {  // the hard case (or g = 0): fill up along the top eigenvector
    const Eigen::Vector2d base = s_lo.allFinite() ? s_lo : Eigen::Vector2d::Zero();
    const Eigen::Vector2d q = Q.col(1);
    // |base + t q| = delta with t >= 0 (base is orthogonal to q up to rounding)
    const double t = std::sqrt(std::max(0.0, delta * delta - base.squaredNorm()));
    return base + (q.dot(g) >= 0 ? t : -t) * q;
  }
  double a = mu_lo + tiny, b = mu_hi;
  for (int it = 0; it < 100 && b - a > 1e-14 * b; ++it) {
    const double m = 0.5 * (a + b);
    (step(m).norm() > delta ? a : b) = m;
  }
  return step(b);
}

}  // namespace

BoxAscentResult box_ascent(const BatchFunction& f, const Eigen::Vector2d& x0, double f0, const Eigen::Vector2d& lo,
                           const Eigen::Vector2d& hi, const BoxAscentOptions& o) {
  if (!(o.h > 0) || !(o.h_min > 0 && o.h_min <= o.h) || !(o.tol.minCoeff() > 0) || !(o.f_tol >= 0) || !(o.delta0 > 0) ||
      !(o.delta_max >= o.delta0) || o.max_batches < 1 || !(o.out_margin > 0) || std::isnan(o.f_out))
    throw std::invalid_argument(
        "box_ascent: h, tol, delta0, out_margin > 0, 0 < h_min <= h, f_tol >= 0, delta_max >= delta0, max_batches >= 1, "
        "f_out not NaN");
  if (!((hi - lo).minCoeff() > 4 * o.h)) throw std::invalid_argument("box_ascent: the box must be wider than 4 h in each coordinate");
  if (!((x0.array() >= lo.array()).all() && (x0.array() <= hi.array()).all()))
    throw std::invalid_argument("box_ascent: the start lies outside the box");
  if (!std::isfinite(f0)) throw std::invalid_argument("box_ascent: f at the start is not finite");
  BoxAscentResult r;
  r.x = x0, r.f = f0;
  auto all_finite = [](const std::vector<double>& v, std::size_t from) {
    for (std::size_t i = from; i < v.size(); ++i)
      if (!std::isfinite(v[i])) return false;
    return true;
  };
  Stencil st = stencil_at(r.x, lo, hi, o.h);
  std::vector<double> sv = f(st.points);
  ++r.batches, r.evaluations += static_cast<int>(st.points.size());
  if (sv.size() != st.points.size()) throw std::logic_error("box_ascent: f gave a value count other than the points'");
  if (!all_finite(sv, 0)) {
    r.finite = false;
    return r;
  }
  double delta = o.delta0;
  while (r.batches < o.max_batches) {
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
    derivatives(st, r.f, sv, g, H);
    // out of reach: the quadratic model's top, f - g'H^-1 g / 2 (H negative definite), with
    // out_margin's room for the model's error, under f_out
    if (o.f_out > -INFINITY && H(0, 0) < 0 && H.determinant() > 0 &&
        r.f - o.out_margin * 0.5 * g.dot(H.ldlt().solve(g)) < o.f_out) {
      r.out_of_reach = true;
      break;
    }
    const Eigen::Vector2d trial = (r.x + trust_step(g, H, delta)).cwiseMax(lo).cwiseMin(hi);
    const Eigen::Vector2d s = trial - r.x;
    const double promised = g.dot(s) + 0.5 * s.dot(H * s);
    if ((s.array().abs() < o.tol.array()).all() || !(promised > o.f_tol)) {
      r.converged = true;
      break;
    }
    // the stencil's step: half this step's length within [h_min, h] (its differences' error
    // is of order h^2: a short step near the top, a short stencil)
    const Stencil next = stencil_at(trial, lo, hi, std::clamp(0.5 * s.norm(), o.h_min, o.h));
    std::vector<Eigen::Vector2d> pts{trial};
    pts.insert(pts.end(), next.points.begin(), next.points.end());
    std::vector<double> v = f(pts);
    ++r.batches, r.evaluations += static_cast<int>(pts.size());
    if (v.size() != pts.size()) throw std::logic_error("box_ascent: f gave a value count other than the points'");
    if (std::isfinite(v[0]) && v[0] > r.f) {
      const double rho = (v[0] - r.f) / promised;
      r.x = trial, r.f = v[0];
      if (!all_finite(v, 1)) {  // a better point whose derivatives cannot be formed: stop there
        r.finite = false;
        return r;
      }
      st = next;
      sv.assign(v.begin() + 1, v.end());
      if (rho > 0.75 && s.norm() >= 0.99 * delta) delta = std::min(2 * delta, o.delta_max);
      else if (rho < 0.25) delta = s.norm() / 4;
    } else {
      delta = s.norm() / 4;
      if ((Eigen::Array2d::Constant(delta) < o.tol.array()).all()) {  // no step at this resolution rises
        r.converged = true;
        break;
      }
    }
  }
  return r;
}

}  // namespace rnav
