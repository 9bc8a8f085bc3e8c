// Unit tests of sim/prl/prl_error_model.hpp: Table 1 radar errors (constant bias + white
// fluctuation given as 2 sigma) and the optional Gauss-Markov drift.
#include "common/physics/prl_effect_columns.hpp"
#include "sim/prl/prl_error_model.hpp"
#include "test/stat_bands.hpp"

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

// The catalogue's deterministic effects are written once (common/physics/prl_effect_columns.hpp): the
// simulator injects C(plot) theta and the diagnosis fits theta on the same C. Here the columns
// against the physics they stand for, by finite differences of the exact polar coordinates, and
// the simulator's injection against the columns times its parameters.
TEST_CASE("catalogue columns: time offset and site offset against finite differences, the simulator injects C theta",
          "[prl][catalogue]") {
  namespace fx = rnav::prl_effect;
  const double az_deg = 253.0;  // an azimuth reference that mixes east and north
  const PlotTruth t = truth_at(120);
  fx::PlotGeometry g;
  g.t_s = t.t_s, g.range_m = t.polar.range_m, g.glide_rad = t.polar.glide_rad;
  g.J = rnav::polar_jacobian(t.p_RA_R);
  g.rate = g.J * t.v_A_R;
  auto polar = [](const Eigen::Vector3d& p) {
    const rnav::Polar q = rnav::polar_from_cartesian(p);
    return Eigen::Vector3d(q.range_m, q.course_rad, q.glide_rad);
  };
  // time_offset: stamped t, taken at t - tau on the straight path p(t) = p0 + v t. Second-order
  // terms: tau^2 |v|^2 / D ~ 1e-8 m for tau = 1 ms at 75 m/s and 20 km; 1e-6 m and 1e-10 rad
  // are far above that and far below the column's size (75 m/s x 1 ms = 0.075 m).
  const double tau = 1e-3;
  const Eigen::Vector3d d_tau = polar(t.p_RA_R - t.v_A_R * tau) - polar(t.p_RA_R);
  const Eigen::Vector3d c_tau = fx::time_offset(g) * tau;
  CHECK(std::abs(d_tau[0] - c_tau[0]) < 1e-6);
  CHECK(std::abs(d_tau[1] - c_tau[1]) < 1e-10);
  CHECK(std::abs(d_tau[2] - c_tau[2]) < 1e-10);
  // site_offset: the radar measures from a site delta away; delta of 0.1 m per axis, second
  // order |delta|^2 / D ~ 1e-6 m.
  const Eigen::Matrix3d R = fx::R_R_ENU(az_deg);
  CHECK((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-15);
  CHECK(R.row(0).cross(R.row(1)).isApprox(R.row(2)));  // right-handed: x cross y = z
  const Eigen::Vector3d delta_enu(0.1, -0.07, 0.05);
  const Eigen::Vector3d d_site = polar(t.p_RA_R + R * delta_enu) - polar(t.p_RA_R);
  const Eigen::Vector3d c_site = fx::site_offset(g, R) * delta_enu;
  CHECK(std::abs(d_site[0] - c_site[0]) < 1e-6);
  CHECK(std::abs(d_site[1] - c_site[1]) < 1e-10);
  CHECK(std::abs(d_site[2] - c_site[2]) < 1e-10);
  // step, drift and periodic sit in their own channel only
  CHECK(fx::bias_step(g, fx::kGlide, 119.0) == Eigen::Vector3d(0, 0, 1));
  CHECK(fx::bias_step(g, fx::kGlide, 121.0) == Eigen::Vector3d(0, 0, 0));
  CHECK(fx::bias_drift(g, fx::kCourse, 20.0) == Eigen::Vector3d(0, 100, 0));
  CHECK_THROWS_AS(fx::periodic(g, fx::kRange, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(fx::bias_step(g, 3, 0.0), std::invalid_argument);

  // The simulator's injection of every deterministic entry at once equals sum C theta.
  rnav::PrlEffectsOptions o;
  o.range_gain = 2e-4, o.time_offset_s = 0.3, o.elevation_refraction_rad = 1e-4;
  o.azimuth_elevation_coupling_rad = 0.01, o.site_offset_east_m = 3, o.site_offset_north_m = -4, o.site_offset_up_m = 5;
  o.drift_range_mps = 0.01, o.drift_course_radps = 1e-6, o.drift_glide_radps = -2e-6;
  o.step_time_s = 100, o.step_range_m = 7, o.step_course_rad = 1e-3, o.step_glide_rad = -2e-3;
  o.periodic_period_s = 30, o.periodic_range_m = 2, o.periodic_course_rad = 3e-4, o.periodic_glide_rad = 4e-4;
  rnav::GeometricEffects effects(o, az_deg);
  Rng rng(1, 0, Stream::kPrl);
  PolarError sys, fl;
  effects.apply(t, rng, sys, fl);
  Eigen::Vector3d want = fx::range_gain(g) * o.range_gain + fx::time_offset(g) * o.time_offset_s +
                         fx::elevation_refraction(g) * o.elevation_refraction_rad +
                         fx::azimuth_elevation_coupling(g) * o.azimuth_elevation_coupling_rad +
                         fx::site_offset(g, R) * Eigen::Vector3d(3, -4, 5);
  const double drift[3] = {0.01, 1e-6, -2e-6}, step[3] = {7, 1e-3, -2e-3}, per[3] = {2, 3e-4, 4e-4};
  for (int c = 0; c < 3; ++c)
    want += fx::bias_drift(g, c, 0) * drift[c] + fx::bias_step(g, c, 100) * step[c] +
            fx::periodic(g, c, 30) * Eigen::Vector2d(per[c], 0);
  const auto got = as_array(sys);
  for (int c = 0; c < 3; ++c) CHECK(got[static_cast<std::size_t>(c)] == Approx(want[c]).epsilon(1e-12));
  CHECK(as_array(fl) == std::array<double, 3>{0, 0, 0});
}
