// Unit tests of common/physics/random.hpp: reproducible streams and the first-order Gauss-Markov process.
#include "common/physics/random.hpp"
#include "test/stat_bands.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using rnav::GaussMarkov;
using rnav::Rng;
using rnav::Stream;
using namespace rnav_test;

TEST_CASE("Rng: same (seed, realization, stream) gives identical draws", "[random]") {
  Rng a(20240611, 17, Stream::kTest), b(20240611, 17, Stream::kTest);
  for (int i = 0; i < 1000; ++i) {
    REQUIRE(a.normal() == b.normal());
    REQUIRE(a.uniform() == b.uniform());
  }
}

TEST_CASE("Rng: a different stream, realization or seed gives different draws", "[random]") {
  auto first = [](Rng r) {
    std::vector<double> v;
    for (int i = 0; i < 8; ++i) v.push_back(r.normal());
    return v;
  };
  const auto base = first(Rng(7, 3, Stream::kPrl));
  for (const auto& other : {first(Rng(7, 3, Stream::kSnsins)), first(Rng(7, 4, Stream::kPrl)),
                            first(Rng(8, 3, Stream::kPrl)), first(Rng(7ull | (1ull << 32), 3, Stream::kPrl)),
                            first(Rng(7, 3ull | (1ull << 32), Stream::kPrl))}) {
    int same = 0;
    for (int i = 0; i < 8; ++i) same += base[i] == other[i];
    CHECK(same == 0);  // independent continuous draws coincide with probability 0
  }
}

TEST_CASE("Rng: uniform lies in 0 inclusive to 1 exclusive", "[random]") {
  Rng r(1, 1, Stream::kTest);
  double lo = 1, hi = 0;
  for (int i = 0; i < 10000; ++i) {
    const double u = r.uniform();
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  CHECK(lo >= 0.0);
  CHECK(hi < 1.0);
  CHECK(lo < 0.01);  // 10000 draws: P(min > 0.01) = 0.99^10000 ~ 2e-44
  CHECK(hi > 0.99);
}

TEST_CASE("GaussMarkov: stationary variance over independent realizations", "[random]") {
  const double sigma = 2.5, tau = 10.0, dt = 1.0;
  const int N = 4000, steps = 30;
  std::vector<double> x0(N), x30(N);
  for (int i = 0; i < N; ++i) {
    Rng rng(4242, i, Stream::kTest);
    GaussMarkov gm(sigma, tau);
    gm.start(rng);
    x0[i] = gm.value();
    for (int k = 0; k < steps; ++k) gm.step(dt, rng);
    x30[i] = gm.value();
  }
  // (N-1) s^2 / sigma^2 ~ chi2(N-1): 99.9 % two-sided band (Wilson-Hilferty), ~ +-7.4 % at N=4000.
  const Band band = variance_ratio_band(N - 1);
  INFO("band [" << band.lo << ", " << band.hi << "]");
  CHECK(band.contains(sample_variance(x0) / (sigma * sigma)));
  CHECK(band.contains(sample_variance(x30) / (sigma * sigma)));
  // zero mean: |mean| < 4 standard errors sigma / sqrt(N)
  CHECK(std::abs(mean(x30)) < 4 * sigma / std::sqrt(N));
}

TEST_CASE("GaussMarkov: correlation at lag tau equals exp(-1)", "[random]") {
  const double sigma = 1.7, tau = 5.0;
  const int N = 4000;
  std::vector<double> a(N), b(N);
  for (int i = 0; i < N; ++i) {
    Rng rng(99, i, Stream::kTest);
    GaussMarkov gm(sigma, tau);
    gm.start(rng);
    gm.step(2.0, rng);
    a[i] = gm.value();
    b[i] = gm.step(tau, rng);  // dt = tau
  }
  const double rho = std::exp(-1.0);
  // Large-sample standard error of a Pearson correlation: (1 - rho^2) / sqrt(N).
  const double se = (1 - rho * rho) / std::sqrt(static_cast<double>(N));
  const double r = correlation(a, b);
  INFO("r = " << r << " expected " << rho << " se " << se);
  // 4 se ~ 0.055 here: a process decorrelating with the wrong time constant (e.g. phi for
  // dt/(2 tau) or 2 dt/tau: rho = 0.61 or 0.14) lies far outside.
  CHECK(std::abs(r - rho) < 4 * se);
}

TEST_CASE("GaussMarkov: infinite tau is a random constant, sigma 0 is zero", "[random]") {
  Rng rng(5, 0, Stream::kTest);
  GaussMarkov c(3.0, std::numeric_limits<double>::infinity());
  c.start(rng);
  const double x = c.value();
  CHECK(x != 0.0);
  for (int k = 0; k < 10; ++k) CHECK(c.step(100.0, rng) == x);
  GaussMarkov z(0.0, 10.0);
  z.start(rng);
  CHECK(z.value() == 0.0);
  CHECK(z.step(1.0, rng) == 0.0);
  // dt = 0 leaves the value unchanged (phi = 1, no noise)
  GaussMarkov g(1.0, 10.0);
  g.start(rng);
  const double g0 = g.value();
  CHECK(g.step(0.0, rng) == g0);
}

TEST_CASE("GaussMarkov: invalid parameters throw", "[random]") {
  CHECK_THROWS_AS(GaussMarkov(-1.0, 10.0), std::invalid_argument);
  CHECK_THROWS_AS(GaussMarkov(std::nan(""), 10.0), std::invalid_argument);
  CHECK_THROWS_AS(GaussMarkov(1.0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(GaussMarkov(1.0, std::nan("")), std::invalid_argument);
  GaussMarkov g(1.0, 1.0);
  Rng rng(1, 1, Stream::kTest);
  CHECK_THROWS_AS(g.step(-0.1, rng), std::invalid_argument);
}
