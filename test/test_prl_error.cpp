// Unit tests of sim/prl/prl_error_model.hpp: Table 1 radar errors (constant bias + white
// fluctuation given as 2 sigma) and the optional Gauss-Markov drift.
#include "prl_error_model.hpp"
#include "stat_bands.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

using rnav::kDegToRad;
using rnav::PlotTruth;
using rnav::PolarError;
using rnav::PrlErrorModel;
using rnav::PrlOptions;
using rnav::Rng;
using rnav::Stream;
using namespace rnav_test;

namespace {
PlotTruth truth_at(double t) {
  PlotTruth p;
  p.t_s = t;
  p.p_RA_R = Eigen::Vector3d(20000 - 75 * t, 400, 1500);
  p.v_A_R = Eigen::Vector3d(-75, 0, 0);
  p.polar = rnav::polar_from_cartesian(p.p_RA_R);
  return p;
}
std::array<double, 3> as_array(const PolarError& e) { return {e.range_m, e.course_rad, e.glide_rad}; }
}  // namespace

TEST_CASE("Table 1 errors: total error mean = bias, sd = (2 sigma)/2", "[prl]") {
  const PrlOptions o;  // Table 1 defaults, no drift
  PrlErrorModel model(o);
  Rng rng(2718, 0, Stream::kPrl);
  model.start(rng);
  const int N = 20000;
  std::array<std::vector<double>, 3> tot;
  long sys_not_bias = 0;
  const std::array<double, 3> bias{o.bias_range_m, o.bias_course_deg * kDegToRad,
                                   o.bias_glide_deg * kDegToRad};
  const std::array<double, 3> sigma{o.noise2s_range_m / 2, o.noise2s_course_deg / 2 * kDegToRad,
                                    o.noise2s_glide_deg / 2 * kDegToRad};
  for (int k = 0; k < N; ++k) {
    PolarError sys, total;
    model.apply(truth_at(k * 1.0), rng, sys, total);
    const auto s = as_array(sys), t = as_array(total);
    for (int c = 0; c < 3; ++c) {
      tot[c].push_back(t[c]);
      // drift off: the systematic part is the configured constant, exactly
      if (s[c] != bias[c]) ++sys_not_bias;
    }
  }
  CHECK(sys_not_bias == 0);
  // (N-1) s^2 / sigma^2 ~ chi2(N-1): 99.9 % band, ~ +-3.3 % at N = 20000.
  const Band band = variance_ratio_band(N - 1);
  for (int c = 0; c < 3; ++c) {
    const double se = sigma[c] / std::sqrt(static_cast<double>(N));  // s.e. of the mean
    INFO("channel " << c << " mean " << mean(tot[c]) << " bias " << bias[c] << " se " << se);
    CHECK(std::abs(mean(tot[c]) - bias[c]) < 4 * se);
    CHECK(band.contains(sample_variance(tot[c]) / (sigma[c] * sigma[c])));
  }
  // the three fluctuations are independent: |r| < 4 / sqrt(N)
  CHECK(std::abs(correlation(tot[0], tot[1])) < 4 / std::sqrt(static_cast<double>(N)));
  CHECK(std::abs(correlation(tot[1], tot[2])) < 4 / std::sqrt(static_cast<double>(N)));
}

TEST_CASE("systematic part equals the configured bias exactly when drift is off", "[prl]") {
  PrlOptions o;
  o.bias_range_m = -13.25;
  o.bias_course_deg = 0.37;
  o.bias_glide_deg = -0.02;
  PrlErrorModel model(o);
  CHECK(model.effects().size() == 2);  // constant bias + white fluctuation
  Rng rng(1, 0, Stream::kPrl);
  model.start(rng);
  for (int k = 0; k < 50; ++k) {
    PolarError sys, total;
    model.apply(truth_at(0.5 * k), rng, sys, total);
    CHECK(sys.range_m == -13.25);
    CHECK(sys.course_rad == 0.37 * kDegToRad);
    CHECK(sys.glide_rad == -0.02 * kDegToRad);
    CHECK(total.range_m != sys.range_m);  // fluctuation is present
  }
}

TEST_CASE("no fluctuation configured: total equals systematic", "[prl]") {
  PrlOptions o;
  o.noise2s_range_m = o.noise2s_course_deg = o.noise2s_glide_deg = 0;
  PrlErrorModel model(o);
  Rng rng(3, 0, Stream::kPrl);
  model.start(rng);
  PolarError sys, total;
  model.apply(truth_at(1.0), rng, sys, total);
  CHECK(total.range_m == sys.range_m);
  CHECK(total.course_rad == sys.course_rad);
  CHECK(total.glide_rad == sys.glide_rad);
}

TEST_CASE("drift on: systematic part = bias + Gauss-Markov with the configured sigma",
          "[prl]") {
  PrlOptions o;
  o.drift_sigma_range_m = 3.0;
  o.drift_sigma_course_deg = 0.05;
  o.drift_sigma_glide_deg = 0.02;
  o.drift_tau_s = 600;
  const int N = 3000;
  std::array<std::vector<double>, 3> dev;
  const std::array<double, 3> bias{o.bias_range_m, o.bias_course_deg * kDegToRad,
                                   o.bias_glide_deg * kDegToRad};
  const std::array<double, 3> sd{3.0, 0.05 * kDegToRad, 0.02 * kDegToRad};
  for (int i = 0; i < N; ++i) {
    PrlErrorModel model(o);
    if (i == 0) CHECK(model.effects().size() == 3);
    Rng rng(555, i, Stream::kPrl);
    model.start(rng);
    PolarError sys, total;
    for (int k = 0; k <= 100; ++k) model.apply(truth_at(k * 1.0), rng, sys, total);
    const auto s = as_array(sys);
    for (int c = 0; c < 3; ++c) dev[c].push_back(s[c] - bias[c]);
  }
  // zero-mean drift: N * mean square / sigma^2 ~ chi2(N), 99.9 % band
  const Band band = variance_ratio_band(N);
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c);
    CHECK(band.contains(mean_square_about(dev[c], 0.0) / (sd[c] * sd[c])));
  }
}
