// Unit tests of estimators/prl_bias/scalar_gm_kalman.hpp: the scalar Gauss-Markov bias filter
// (docs/method.md section 1, equation (11) corrected).
#include "common/physics/random.hpp"
#include "estimators/prl_bias/scalar_gm_kalman.hpp"
#include "test/stat_bands.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using rnav::ScalarGmKalman;
using namespace rnav_test;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
struct Params {
  double delta, tau, dt, r;
};
// range channel (paper-like), a fast bias, a course-like channel in rad, noise-dominated
const std::vector<Params> kParams{{10, 3600, 1, 144}, {2, 5, 1, 4}, {0.0035, 3600, 1, 1.9e-5},
                                  {1, 100, 0.5, 1e4}};
}  // namespace

TEST_CASE("first update initialises with eta = chi and p = r", "[kf]") {
  ScalarGmKalman kf(10, 3600);
  CHECK_FALSE(kf.initialized());
  CHECK(kf.update(3.0, 7.5, 144) == 1.0);
  CHECK(kf.initialized());
  CHECK(kf.eta() == 7.5);
  CHECK(kf.p() == 144);
  kf.reset();
  CHECK_FALSE(kf.initialized());
  CHECK(kf.update(10.0, -2.0, 9) == 1.0);
  CHECK(kf.eta() == -2.0);
  CHECK(kf.p() == 9);
}

TEST_CASE("second update follows the corrected equations (11)", "[kf]") {
  const double delta = 3, tau = 20, r1 = 4, r2 = 6, dt = 2.5, chi1 = 1.0, chi2 = 4.0;
  ScalarGmKalman kf(delta, tau);
  kf.update(0.0, chi1, r1);
  const double K = kf.update(dt, chi2, r2);
  const double phi = std::exp(-dt / tau), q = delta * delta * (1 - phi * phi);
  const double m = phi * phi * r1 + q;  // phi^2, not phi (the paper's slip)
  const double Ke = m / (m + r2);
  CHECK(K == Approx(Ke).epsilon(1e-14));
  CHECK(kf.eta() == Approx(phi * chi1 + Ke * (chi2 - phi * chi1)).epsilon(1e-14));
  CHECK(kf.p() == Approx(Ke * r2).epsilon(1e-14));
}

TEST_CASE("steady_state satisfies the Riccati fixed point", "[kf]") {
  for (const auto& P : kParams) {
    const auto ss = ScalarGmKalman::steady_state(P.delta, P.tau, P.dt, P.r);
    const double phi = std::exp(-P.dt / P.tau), q = P.delta * P.delta * (1 - phi * phi);
    INFO("delta " << P.delta << " tau " << P.tau << " r " << P.r);
    CHECK(ss.m > 0);
    CHECK(ss.m == Approx(phi * phi * ss.p + q).epsilon(1e-12));  // prediction
    CHECK(ss.p == Approx(ss.m * P.r / (ss.m + P.r)).epsilon(1e-12));  // update
    CHECK(ss.gain == Approx(ss.m / (ss.m + P.r)).epsilon(1e-12));
  }
}

TEST_CASE("gain and variance converge to steady_state for constant dt and r", "[kf]") {
  for (const auto& P : kParams) {
    ScalarGmKalman kf(P.delta, P.tau);
    double K = 0;
    // The Riccati error contracts by ~ (phi (1 - K))^2 per step; the slowest case here has
    // K ~ 1e-3, phi ~ 0.995 (contraction ~ 0.988), so 20000 steps reach machine precision.
    for (int k = 0; k < 20000; ++k) K = kf.update(k * P.dt, 0.1 * std::sin(0.3 * k), P.r);
    const auto ss = ScalarGmKalman::steady_state(P.delta, P.tau, P.dt, P.r);
    INFO("delta " << P.delta << " tau " << P.tau << " r " << P.r);
    CHECK(K == Approx(ss.gain).epsilon(1e-9));
    CHECK(kf.p() == Approx(ss.p).epsilon(1e-9));
  }
}

TEST_CASE("tau = infinity: the filter is the running mean, p = r / N", "[kf]") {
  const double r = 144, bias = 6.0;
  ScalarGmKalman kf(10, kInf);
  rnav::Rng rng(11, 0, rnav::Stream::kTest);
  double sum = 0;
  for (int n = 1; n <= 1000; ++n) {
    const double chi = bias + std::sqrt(r) * rng.normal();
    sum += chi;
    kf.update(n * 1.0, chi, r);
    INFO("N = " << n);
    REQUIRE(kf.p() == Approx(r / n).epsilon(1e-9));
    REQUIRE(kf.eta() == Approx(sum / n).epsilon(1e-9));
  }
  // and the running mean of 1000 samples is within 4 s.e. (sqrt(r/N)) of the bias
  CHECK(std::abs(kf.eta() - bias) < 4 * std::sqrt(r / 1000));
  const auto ss = ScalarGmKalman::steady_state(10, kInf, 1.0, r);
  CHECK(ss.gain == 0.0);
  CHECK(ss.p == 0.0);
}

TEST_CASE("filter consistency: Monte Carlo error variance equals p", "[kf]") {
  // Truth: Gauss-Markov eta with the filter's own (delta, tau), observed in white noise r.
  // Initialising with eta_hat = chi(1), p = r makes the first error exactly omega(1) ~ N(0, r),
  // and the recursion then keeps Var(eta_hat - eta) = p at every step (the gain is optimal),
  // whatever the truth's prior.
  const double delta = 2, tau = 8, dt = 1, r = 3;
  const int M = 4000, steps = 60;
  const double phi = std::exp(-dt / tau), sq = delta * std::sqrt(1 - phi * phi);
  std::vector<double> err1(M), err10(M), errN(M);
  double p1 = 0, p10 = 0, pN = 0;
  for (int i = 0; i < M; ++i) {
    rnav::Rng rng(8080, i, rnav::Stream::kTest);
    ScalarGmKalman kf(delta, tau);
    double eta = delta * rng.normal();
    for (int k = 0; k < steps; ++k) {
      if (k > 0) eta = phi * eta + sq * rng.normal();
      kf.update(k * dt, eta + std::sqrt(r) * rng.normal(), r);
      if (k == 0) err1[i] = kf.eta() - eta, p1 = kf.p();
      if (k == 9) err10[i] = kf.eta() - eta, p10 = kf.p();
    }
    errN[i] = kf.eta() - eta;
    pN = kf.p();
  }
  // p is deterministic (constant dt, r), so M * mean(err^2) / p ~ chi2(M): 99.9 % band
  // (Wilson-Hilferty), ~ +-7.4 % at M = 4000.
  const Band band = variance_ratio_band(M);
  INFO("band [" << band.lo << ", " << band.hi << "]");
  CHECK(band.contains(mean_square_about(err1, 0.0) / p1));
  CHECK(band.contains(mean_square_about(err10, 0.0) / p10));
  CHECK(band.contains(mean_square_about(errN, 0.0) / pN));
  // unbiased: |mean error| < 4 s.e.
  CHECK(std::abs(mean(errN)) < 4 * std::sqrt(pN / M));
  // p has shrunk well below r by the end (so the check above is not the trivial p = r one)
  CHECK(pN < 0.5 * r);
}

TEST_CASE("invalid inputs throw", "[kf]") {
  CHECK_THROWS_AS(ScalarGmKalman(0, 10), std::invalid_argument);
  CHECK_THROWS_AS(ScalarGmKalman(1, 0), std::invalid_argument);
  ScalarGmKalman kf(1, 10);
  CHECK_THROWS_AS(kf.update(0, 1, 0), std::invalid_argument);
  CHECK_THROWS_AS(kf.update(0, std::nan(""), 1), std::invalid_argument);
  kf.update(5, 1, 1);
  CHECK_THROWS_AS(kf.update(4, 1, 1), std::invalid_argument);  // time went backwards
}
