// Unit tests of estimators/prl_bias/nav_interpolator.hpp: cubic Hermite interpolation of the
// navigation solution and the plot-time decision rule of NavBuffer.
#include "estimators/prl_bias/nav_interpolator.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <stdexcept>
#include <vector>

using rnav::hermite_position;
using rnav::NavBuffer;
using rnav::NavInR;
using Decision = rnav::NavBuffer::Decision;

namespace {

constexpr std::int64_t kEpoch = 1767225600000000LL;  // realistic utime magnitude
constexpr std::int64_t kMs = 1000;

// p(t) = c0 + c1 t + c2 t^2 + c3 t^3 (t in s from kEpoch), with its exact derivative.
struct Cubic {
  Eigen::Vector3d c0, c1, c2, c3;
  Eigen::Vector3d p(double t) const { return c0 + t * (c1 + t * (c2 + t * c3)); }
  Eigen::Vector3d v(double t) const { return c1 + t * (2 * c2 + 3 * t * c3); }
  NavInR sample(std::int64_t utime) const {
    NavInR n;
    n.utime = utime;
    n.link_utime = utime + 300 * kMs;
    const double t = (utime - kEpoch) * 1e-6;
    n.p_RA_R = p(t);
    n.v_A_R = v(t);
    n.sigma_pos_m = 2;
    return n;
  }
};

NavInR sol(std::int64_t utime_ms, std::int64_t link_ms) {
  NavInR n;
  n.utime = kEpoch + utime_ms * kMs;
  n.link_utime = kEpoch + link_ms * kMs;
  n.p_RA_R = Eigen::Vector3d(utime_ms, 0, 0);
  n.v_A_R = Eigen::Vector3d(1000, 0, 0);
  return n;
}
std::int64_t at_ms(std::int64_t ms) { return kEpoch + ms * kMs; }

}  // namespace

TEST_CASE("hermite_position is exact for cubic and quadratic motion with exact velocities",
          "[nav]") {
  const std::vector<Cubic> paths{
      {{20000, 400, 1500}, {-75, -3.5, 2}, {0.4, 0.01, -0.3}, {0.02, -0.001, 0.005}},  // cubic
      {{-3000, 50, -200}, {60, 0, -40}, {1.5, -0.2, 0.7}, {0, 0, 0}}};                 // quadratic
  for (const auto& c : paths) {
    for (std::int64_t ta_ms : {1000LL, 123250LL}) {
      const NavInR a = c.sample(at_ms(ta_ms)), b = c.sample(at_ms(ta_ms + 500));
      for (std::int64_t dms = 0; dms <= 500; dms += 25) {
        const std::int64_t t = at_ms(ta_ms + dms);
        const Eigen::Vector3d exact = c.p((t - kEpoch) * 1e-6);
        INFO("t - ta = " << dms << " ms");
        // Exact up to rounding of ~2e4 m coordinates (eps * 2e4 ~ 5e-12 m).
        CHECK((hermite_position(a, b, t) - exact).norm() < 1e-8);
      }
    }
  }
  // The velocity terms matter: with velocities zeroed the midpoint would be wrong.
  const Cubic& c = paths[0];
  NavInR a = c.sample(at_ms(1000)), b = c.sample(at_ms(3000));
  a.v_A_R.setZero();
  b.v_A_R.setZero();
  CHECK((hermite_position(a, b, at_ms(2000)) - c.p(2.0)).norm() > 0.1);
}

TEST_CASE("hermite_position with coincident solutions returns the position", "[nav]") {
  const NavInR a = sol(1000, 1300);
  CHECK(hermite_position(a, a, a.utime) == a.p_RA_R);
}

TEST_CASE("NavBuffer::decide: interpolate, wait and dropout", "[nav]") {
  // Solutions every 500 ms, 300 ms latency; plot at 1200 ms; wait 1 s (deadline 2200 ms);
  // max gap 2 s.
  const std::int64_t t = at_ms(1200), wait = 1000 * kMs, gap = 2000 * kMs, deadline = t + wait;
  NavBuffer buf;
  for (std::int64_t k = 0; k <= 2; ++k) buf.add(sol(500 * k, 500 * k + 300));  // 0, 500, 1000

  SECTION("no solution after t yet: wait up to and including the deadline") {
    CHECK(buf.decide(t, wait, gap, at_ms(1300)).decision == Decision::kWait);
    CHECK(buf.decide(t, wait, gap, deadline).decision == Decision::kWait);  // boundary
    CHECK(buf.decide(t, wait, gap, deadline + 1).decision == Decision::kDropout);
  }
  SECTION("the bracketing solution arrives in time: interpolate between neighbours") {
    buf.add(sol(1500, 1800));
    buf.add(sol(2000, 2300));
    for (std::int64_t now : {at_ms(1801), deadline, deadline + 1, at_ms(10000)}) {
      const auto r = buf.decide(t, wait, gap, now);
      REQUIRE(r.decision == Decision::kInterpolate);
      REQUIRE(r.before);
      REQUIRE(r.after);
      CHECK(r.before->utime == at_ms(1000));
      CHECK(r.after->utime == at_ms(1500));
    }
  }
  SECTION("the bracketing solution arrives exactly at the deadline: interpolate") {
    buf.add(sol(1500, 2200));
    CHECK(buf.decide(t, wait, gap, deadline + 1).decision == Decision::kInterpolate);
  }
  SECTION("the bracketing solution arrives after the deadline: wait, then dropout") {
    buf.add(sol(1500, 2201));
    CHECK(buf.decide(t, wait, gap, deadline).decision == Decision::kWait);
    CHECK(buf.decide(t, wait, gap, at_ms(3000)).decision == Decision::kDropout);
  }
  SECTION("plot exactly at a solution's time: before == after == that solution") {
    const auto r = buf.decide(at_ms(1000), wait, gap, at_ms(5000));
    REQUIRE(r.decision == Decision::kInterpolate);
    CHECK(r.before->utime == at_ms(1000));
    CHECK(r.after->utime == at_ms(1000));
  }
  SECTION("plot before the first solution: dropout (nothing to interpolate from)") {
    buf.clear();
    buf.add(sol(1500, 1800));
    CHECK(buf.decide(t, wait, gap, at_ms(5000)).decision == Decision::kDropout);
  }
}

TEST_CASE("NavBuffer::decide: a gap larger than max_gap is a dropout", "[nav]") {
  const std::int64_t t = at_ms(1200), wait = 5000 * kMs;
  NavBuffer buf;
  buf.add(sol(0, 300));
  buf.add(sol(3000, 3300));  // gap 3 s around the plot, arrives before t + wait
  const std::int64_t now = at_ms(7000);
  CHECK(buf.decide(t, wait, 2000 * kMs, now).decision == Decision::kDropout);
  CHECK(buf.decide(t, wait, 2999 * kMs, now).decision == Decision::kDropout);
  CHECK(buf.decide(t, wait, 3000 * kMs, now).decision == Decision::kInterpolate);  // gap == max
  CHECK(buf.decide(t, wait, 4000 * kMs, now).decision == Decision::kInterpolate);
}

TEST_CASE("NavBuffer::add rejects out-of-order arrivals", "[nav]") {
  NavBuffer buf;
  buf.add(sol(1000, 1300));
  CHECK_THROWS_AS(buf.add(sol(1500, 1299)), std::runtime_error);  // link_utime decreased
  CHECK_THROWS_AS(buf.add(sol(1000, 1400)), std::runtime_error);  // validity not increasing
  CHECK_THROWS_AS(buf.add(sol(900, 1400)), std::runtime_error);
  CHECK(buf.size() == 1);
  CHECK_NOTHROW(buf.add(sol(1500, 1300)));  // equal arrival time is fine
  CHECK(buf.size() == 2);
}

TEST_CASE("NavBuffer::prune_before keeps what later plots need", "[nav]") {
  NavBuffer full, pruned;
  for (std::int64_t k = 0; k <= 20; ++k) {
    full.add(sol(500 * k, 500 * k + 300));
    pruned.add(sol(500 * k, 500 * k + 300));
  }
  const std::int64_t gap = 2000 * kMs, wait = 1000 * kMs;
  pruned.prune_before(at_ms(6100), gap);
  CHECK(pruned.size() < full.size());
  for (std::int64_t ms = 6100; ms <= 10000; ms += 130) {
    const auto a = full.decide(at_ms(ms), wait, gap, at_ms(20000));
    const auto b = pruned.decide(at_ms(ms), wait, gap, at_ms(20000));
    INFO("plot at " << ms << " ms");
    CHECK(a.decision == b.decision);
    if (a.decision == Decision::kInterpolate && b.decision == Decision::kInterpolate) {
      CHECK(a.before->utime == b.before->utime);
      CHECK(a.after->utime == b.after->utime);
    }
  }
}

TEST_CASE("nav_to_radar_frame converts position and NED velocity into R", "[nav]") {
  const rnav::LocalLevelFrame R({48.1, 16.58, 232.0}, 115.9);
  const Eigen::Vector3d p(15000, 600, -2000);
  const rnav::Geodetic g = R.to_geodetic(p);
  rnav::nav_solution_t n{};
  n.utime = at_ms(1000);
  n.link_utime = at_ms(1300);
  n.lat_deg = g.lat_deg;
  n.lon_deg = g.lon_deg;
  n.h_m = g.h_m;
  n.v_N[0] = 30;
  n.v_N[1] = -65;
  n.v_N[2] = 3.5;
  n.sigma_pos_m = 2.5;
  const NavInR r = rnav::nav_to_radar_frame(n, R);
  CHECK((r.p_RA_R - p).norm() < 1e-4);
  CHECK((R.to_ned(g, r.v_A_R) - Eigen::Vector3d(30, -65, 3.5)).norm() < 1e-12);
  CHECK(r.utime == n.utime);
  CHECK(r.link_utime == n.link_utime);
  CHECK(r.sigma_pos_m == 2.5);
}
