// The trust-region ascent that refines the noise identification (box_ascent): maxima it must
// reach, the box it must keep, what it does with values that are not finite, and its refusals.
#include "estimators/model_id/box_ascent.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace rnav;

namespace {

// f evaluated point by point, counting points and batches, every point checked inside the box.
struct Counted {
  std::function<double(const Eigen::Vector2d&)> f;
  Eigen::Vector2d lo, hi;
  int points = 0, batches = 0, outside = 0;
  std::size_t widest = 0;
  BatchFunction batch() {
    return [this](const std::vector<Eigen::Vector2d>& ps) {
      ++batches;
      widest = std::max(widest, ps.size());
      std::vector<double> v;
      for (const Eigen::Vector2d& p : ps) {
        ++points;
        outside += (p.array() < lo.array()).any() || (p.array() > hi.array()).any();
        v.push_back(f(p));
      }
      return v;
    };
  }
};

}  // namespace

TEST_CASE("box ascent: a concave quadratic's maximum inside the box, in a few batches", "[model_id][ascent]") {
  // f = -(x - m)' A (x - m) / 2 with correlated A: the finite differences of a quadratic are
  // exact, so Newton reaches m in one step once the radius allows it; the stop comes at the
  // next step, under tol (1e-3). Started 3 units away with radius 1: at most 3 trust-limited
  // steps, one Newton step and the stencil: 6 batches.
  const Eigen::Vector2d m(2.3, -1.7);
  Eigen::Matrix2d A;
  A << 2.0, 0.8, 0.8, 1.0;
  Counted c{[&](const Eigen::Vector2d& x) { return -0.5 * (x - m).dot(A * (x - m)); }, {-5, -5}, {5, 5}};
  const Eigen::Vector2d x0(0, 0);
  BoxAscentOptions o;
  const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, o);
  CHECK(r.converged);
  CHECK(r.finite);
  CHECK((r.x - m).cwiseAbs().maxCoeff() < 1e-3);
  CHECK(r.f == c.f(r.x));
  CHECK(r.batches == c.batches);
  CHECK(r.evaluations == c.points);
  CHECK(r.batches <= 6);
  CHECK(c.widest <= 6);
  CHECK(c.outside == 0);
}

TEST_CASE("box ascent: a curved ridge is followed to its top", "[model_id][ascent]") {
  // The log-likelihood of a small correlated share has the shape of a bent ridge in (log tau,
  // logit lambda). Rosenbrock's, negated and scaled: f = -(1 - x)^2 - 5 (y - x^2)^2, top at
  // (1, 1), started at (-1, 1.5) across the bend; the value there is within 1e-6 of 0 only
  // once the point is within about 1e-3 of the top.
  Counted c{[](const Eigen::Vector2d& p) { return -std::pow(1 - p(0), 2) - 5 * std::pow(p(1) - p(0) * p(0), 2); },
            {-3, -3},
            {3, 3}};
  const Eigen::Vector2d x0(-1, 1.5);
  BoxAscentOptions o;
  o.max_batches = 40;
  const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, o);
  CHECK(r.converged);
  CHECK((r.x - Eigen::Vector2d(1, 1)).cwiseAbs().maxCoeff() < 1e-2);
  CHECK(r.f > -1e-4);
  CHECK(c.outside == 0);
}

TEST_CASE("box ascent: a maximum beyond the box ends on its face, the stencil kept inside", "[model_id][ascent]") {
  // f rises in x without bound and has its maximum in y at 0.4: the answer is (hi_x, 0.4), the
  // stencil there one-sided in x (a central one would step outside).
  Counted c{[](const Eigen::Vector2d& p) { return 3 * p(0) - std::pow(p(1) - 0.4, 2); }, {0, -2}, {4, 2}};
  const Eigen::Vector2d x0(1, -1);
  BoxAscentOptions o;
  o.max_batches = 20;
  const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, o);
  CHECK(r.converged);
  CHECK(r.x(0) == 4);
  CHECK(std::abs(r.x(1) - 0.4) < 1e-3);
  CHECK(c.outside == 0);
}

TEST_CASE("box ascent: never worse than the start, and f_tol stops a climb too small to matter", "[model_id][ascent]") {
  // A nearly flat bowl-shaped function (its rises of 1e-9) from a start near its top: with
  // f_tol 1e-6 no step is taken; with 0 it climbs, never to a value below the start.
  auto flat = [](const Eigen::Vector2d& p) { return -1e-9 * (p - Eigen::Vector2d(0.5, 0.5)).squaredNorm(); };
  const Eigen::Vector2d x0(0.2, 0.9);
  {
    Counted c{flat, {-2, -2}, {2, 2}};
    BoxAscentOptions o;
    o.f_tol = 1e-6;
    const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, o);
    CHECK(r.converged);
    CHECK(r.batches == 1);  // the stencil only
    CHECK(r.x == x0);
  }
  {
    Counted c{flat, {-2, -2}, {2, 2}};
    const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, BoxAscentOptions{});
    CHECK(r.f >= c.f(x0));
    CHECK((r.x - Eigen::Vector2d(0.5, 0.5)).norm() < (x0 - Eigen::Vector2d(0.5, 0.5)).norm());
  }
}

TEST_CASE("box ascent: a value that is not finite stops it at the last good point, flagged", "[model_id][ascent]") {
  // f is -inf for x > 1 (a model leaving no spread): a step there is refused; a stencil that
  // reaches it gives no derivatives, and the result says so (the caller then takes its line
  // searches).
  auto f = [](const Eigen::Vector2d& p) {
    return p(0) > 1 ? -std::numeric_limits<double>::infinity() : p(0) - 0.1 * p(1) * p(1);
  };
  Counted c{f, {-2, -2}, {2, 2}};
  const Eigen::Vector2d x0(0, 1);
  const BoxAscentResult r = box_ascent(c.batch(), x0, c.f(x0), c.lo, c.hi, BoxAscentOptions{});
  CHECK_FALSE(r.finite);
  CHECK(std::isfinite(r.f));
  CHECK(r.f >= c.f(x0));
  CHECK(r.x(0) <= 1);
}

TEST_CASE("box ascent: bad input is refused, naming what", "[model_id][ascent]") {
  Counted c{[](const Eigen::Vector2d& p) { return -p.squaredNorm(); }, {-1, -1}, {1, 1}};
  const BoxAscentOptions o;
  CHECK_THROWS_WITH(box_ascent(c.batch(), {2, 0}, -4, c.lo, c.hi, o), Catch::Contains("outside the box"));
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, NAN, c.lo, c.hi, o), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, 0, {-0.05, -1}, {0.05, 1}, o), Catch::Contains("wider than 4 h"));
  BoxAscentOptions bad = o;
  bad.delta_max = 0.5;  // below delta0
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, 0, c.lo, c.hi, bad), Catch::Contains("delta_max"));
  bad = o;
  bad.f_tol = -1;
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, 0, c.lo, c.hi, bad), Catch::Contains("f_tol"));
  bad = o;
  bad.out_margin = 0;
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, 0, c.lo, c.hi, bad), Catch::Contains("out_margin"));
  bad = o;
  bad.f_out = NAN;
  CHECK_THROWS_WITH(box_ascent(c.batch(), {0, 0}, 0, c.lo, c.hi, bad), Catch::Contains("f_out"));
  CHECK(c.points == 0);  // nothing evaluated before refusing
}

TEST_CASE("box ascent: a hill whose top stays under f_out is given up", "[model_id][ascent]") {
  // f = 1 - (x - m)' A (x - m) / 2, its top 1 at m; started 3 units away, f0 = -3.07. The
  // stencils' quadratic model is exact (its top is 1), so with out_margin 10 the climb is given
  // up once f + 10 (1 - f) < f_out: at once for f_out 40 (f0 + 10 (1 - f0) = 37.6); for f_out
  // 1.5, above the top, once f > 17/18 on the way; never where the top is above f_out (0.5)
  // or without f_out: there it converges to m as before.
  const Eigen::Vector2d m(2.3, -1.7);
  Eigen::Matrix2d A;
  A << 2.0, 0.8, 0.8, 1.0;
  const auto f = [&](const Eigen::Vector2d& x) { return 1 - 0.5 * (x - m).dot(A * (x - m)); };
  const Eigen::Vector2d x0(0, 0);
  for (const double f_out : {40.0, 1.5, 0.5, -std::numeric_limits<double>::infinity()}) {
    Counted c{f, {-5, -5}, {5, 5}};
    BoxAscentOptions o;
    o.f_out = f_out;
    const BoxAscentResult r = box_ascent(c.batch(), x0, f(x0), c.lo, c.hi, o);
    INFO("f_out " << f_out << ": batches " << r.batches << ", f " << r.f);
    CHECK(r.out_of_reach == (f_out > 1));
    if (f_out == 40.0) {
      CHECK(r.batches == 1);
      CHECK(r.x == x0);
    } else if (f_out == 1.5) {
      CHECK(r.f > 17.0 / 18 - 1e-9);
      CHECK(r.f <= 1);
    } else {
      CHECK(r.converged);
      CHECK((r.x - m).cwiseAbs().maxCoeff() < 1e-3);
    }
  }
}
