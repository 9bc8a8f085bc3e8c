// Unit tests of sim/snsins/snsins_error_model.hpp: SNS/INS position and velocity errors.
#include "sim/snsins/snsins_error_model.hpp"
#include "test/stat_bands.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

using rnav::Rng;
using rnav::SnsinsErrorModel;
using rnav::SnsinsOptions;
using rnav::Stream;
using namespace rnav_test;

namespace {

// Run N independent realizations on the link grid t = phase + k period (the node's schedule)
// and return, per axis, the position error at the last two samples and the velocity error.
struct Samples {
  std::array<std::vector<double>, 3> prev, last, vel;
};
Samples run(const SnsinsOptions& o, int N, int steps, std::uint64_t seed) {
  Samples s;
  for (int a = 0; a < 3; ++a) {
    s.prev[a].resize(N);
    s.last[a].resize(N);
    s.vel[a].resize(N);
  }
  for (int i = 0; i < N; ++i) {
    Rng rng(seed, i, Stream::kSnsins);
    SnsinsErrorModel m(o);
    m.start(rng);
    for (int k = 0; k < steps; ++k) {
      m.step(o.link_phase_s + k * o.link_period_s, rng);
      if (k == steps - 2)
        for (int a = 0; a < 3; ++a) s.prev[a][i] = m.dp_L()[a];
    }
    for (int a = 0; a < 3; ++a) {
      s.last[a][i] = m.dp_L()[a];
      s.vel[a][i] = m.dv_L()[a];
    }
  }
  return s;
}

}  // namespace

TEST_CASE("sigma_smooth_m = white_sigma sqrt(a / (2 - a)), a = sns_period / ins_tau", "[snsins]") {
  SnsinsOptions o;
  const SnsinsErrorModel m(o);
  const double a = o.sns_period_s / o.ins_tau_s;
  CHECK(m.sigma_smooth_m() == Approx(o.white_sigma_m * std::sqrt(a / (2 - a))).epsilon(1e-14));
  // Independent derivation: iterate the variance of y(k+1) = (1-a) y(k) + a x(k) to its
  // fixed point v = (1-a)^2 v + a^2 sigma_w^2.
  double v = 0;
  for (int k = 0; k < 20000; ++k) v = (1 - a) * (1 - a) * v + a * a * o.white_sigma_m * o.white_sigma_m;
  CHECK(m.sigma_smooth_m() == Approx(std::sqrt(v)).epsilon(1e-12));
  CHECK(m.sigma_pos_m() ==
        Approx(std::sqrt(o.corr_sigma_m * o.corr_sigma_m + v)).epsilon(1e-12));
}

TEST_CASE("with ins_tau_s = 0 (or below the SNS period) the white part is not smoothed",
          "[snsins]") {
  for (double tau : {0.0, 0.05}) {
    SnsinsOptions o;
    o.ins_tau_s = tau;
    const SnsinsErrorModel m(o);
    CHECK(m.sigma_smooth_m() == o.white_sigma_m);
    CHECK(m.sigma_pos_m() == Approx(std::hypot(o.corr_sigma_m, o.white_sigma_m)).epsilon(1e-14));
  }
}

TEST_CASE("per-axis RMS position error equals sigma_pos_m over the ensemble", "[snsins]") {
  const SnsinsOptions o;  // defaults: corr 1.9 m / 120 s, white 0.62 m smoothed by the INS
  const int N = 3000;
  const Samples s = run(o, N, 121, 777);  // last sample at t = 60.25 s
  const double sp = SnsinsErrorModel(o).sigma_pos_m();
  // Zero-mean errors: N * (mean square) / sigma^2 ~ chi2(N); 99.9 % band (Wilson-Hilferty),
  // ~ +-8.5 % in the variance at N = 3000.
  const Band band = variance_ratio_band(N);
  for (int a = 0; a < 3; ++a) {
    const double ratio = mean_square_about(s.last[a], 0.0) / (sp * sp);
    INFO("axis " << a << " ms/sigma^2 = " << ratio << " band [" << band.lo << ", " << band.hi << "]");
    CHECK(band.contains(ratio));
    const double rv = mean_square_about(s.vel[a], 0.0) / (o.vel_sigma_mps * o.vel_sigma_mps);
    CHECK(band.contains(rv));
  }
}

TEST_CASE("smoothed white part alone: stationary sigma and correlation over one link period",
          "[snsins]") {
  SnsinsOptions o;
  o.corr_sigma_m = 0;  // isolate e_smooth
  const int N = 3000;
  const Samples s = run(o, N, 41, 31337);
  const SnsinsErrorModel m(o);
  const Band band = variance_ratio_band(N);
  // The INS filter y(k+1) = (1-a) y(k) + a x(k) at the SNS rate: over one link period the
  // correlation is (1-a)^(link_period / sns_period).
  const double a = o.sns_period_s / o.ins_tau_s;
  const double rho = std::pow(1 - a, o.link_period_s / o.sns_period_s);
  const double se = (1 - rho * rho) / std::sqrt(static_cast<double>(N));  // Pearson r's s.e.
  for (int ax = 0; ax < 3; ++ax) {
    const double sm = m.sigma_smooth_m();
    CHECK(band.contains(mean_square_about(s.last[ax], 0.0) / (sm * sm)));
    const double r = correlation(s.prev[ax], s.last[ax]);
    INFO("axis " << ax << " r = " << r << " expected " << rho << " se " << se);
    CHECK(std::abs(r - rho) < 4 * se);
  }
}

TEST_CASE("ins_tau_s = 0: the white part is white with sigma white_sigma_m", "[snsins]") {
  SnsinsOptions o;
  o.corr_sigma_m = 0;
  o.ins_tau_s = 0;
  const int N = 3000;
  const Samples s = run(o, N, 11, 4711);
  const Band band = variance_ratio_band(N);
  for (int ax = 0; ax < 3; ++ax) {
    CHECK(band.contains(mean_square_about(s.last[ax], 0.0) / (o.white_sigma_m * o.white_sigma_m)));
    // independent consecutive samples: |r| < 4 / sqrt(N) (s.e. of r at rho = 0)
    CHECK(std::abs(correlation(s.prev[ax], s.last[ax])) < 4 / std::sqrt(static_cast<double>(N)));
  }
}
