// Unit tests of estimators/prl_bias/prl_bias_estimator.hpp: pseudo-measurement, estimation,
// switch to compensation, nav drop-outs, course wrap-around.
#include "estimators/prl_bias/prl_bias_estimator.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <optional>

using rnav::kDegToRad;
using rnav::NavAtPlot;
using rnav::PrlBiasEstimator;
using rnav::PrlBiasOptions;
using rnav::prl_bias_estimate_t;
using rnav::prl_plot_t;

namespace {

constexpr std::int64_t kEpoch = 1767225600000000LL;
// LCM's in-class `static const int8_t` mode constants have no out-of-class definition; copy them
// into constant expressions so Catch's by-reference comparisons do not ODR-use them.
constexpr int kNoEstimate = rnav::prl_bias_estimate_t::NO_ESTIMATE;
constexpr int kEstimating = rnav::prl_bias_estimate_t::ESTIMATING;
constexpr int kCompensating = rnav::prl_bias_estimate_t::COMPENSATING;
constexpr int kNavDropout = rnav::prl_bias_estimate_t::NAV_DROPOUT;
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kBias[3] = {6.0, 0.1 * kDegToRad, 0.15 * kDegToRad};  // Table 1

Eigen::Vector3d truth_at(double t) { return {20000 - 45 * t, 400 - 0.5 * t, 1500 + 2 * t}; }

std::int64_t utime_of(double t) { return kEpoch + std::llround(t * 1e6); }

// A plot of the true position plus a constant polar bias, zero noise.
prl_plot_t plot_of(const Eigen::Vector3d& p, double t, const double bias[3], std::int64_t id = 0) {
  const rnav::Polar q = rnav::polar_from_cartesian(p);
  prl_plot_t pl{};
  pl.utime = utime_of(t);
  pl.plot_id = id;
  pl.range_m = q.range_m + bias[0];
  pl.course_rad = rnav::wrap_pi(q.course_rad + bias[1]);
  pl.glide_rad = q.glide_rad + bias[2];
  return pl;
}

PrlBiasOptions constant_bias_options() {
  PrlBiasOptions o;  // switch at 400 s
  o.tau_s = kInf;    // random-constant model: the estimate of a constant bias is exact
  return o;
}

}  // namespace

TEST_CASE("zero noise, nav at truth: eta equals the bias, compensated plot equals truth",
          "[estimator]") {
  PrlBiasEstimator est(constant_bias_options(), kEpoch);
  prl_bias_estimate_t last{};
  for (int k = 0; k < 400; ++k) {
    const double t = k;
    const Eigen::Vector3d p = truth_at(t);
    const prl_plot_t pl = plot_of(p, t, kBias, k);
    const auto out = est.process(pl, NavAtPlot{p, 2.0});
    REQUIRE(out.estimate.mode == kEstimating);
    REQUIRE(out.estimate.has_chi);
    // chi = plot - nav = the bias (nav exact, no noise); rounding of 2e4 m ranges ~ 4e-12 m
    CHECK(out.estimate.chi[0] == Approx(kBias[0]).margin(1e-9));
    CHECK(out.estimate.chi[1] == Approx(kBias[1]).margin(1e-12));
    CHECK(out.estimate.chi[2] == Approx(kBias[2]).margin(1e-12));
    // estimating, not compensating (compensate_during_estimation = false): plot passes through
    CHECK(out.compensated.range_m == pl.range_m);
    CHECK(out.compensated.course_rad == pl.course_rad);
    CHECK(out.compensated.glide_rad == pl.glide_rad);
    CHECK(out.compensated.plot_id == k);
    last = out.estimate;
  }
  CHECK(last.eta[0] == Approx(kBias[0]).margin(1e-9));
  CHECK(last.eta[1] == Approx(kBias[1]).margin(1e-12));
  CHECK(last.eta[2] == Approx(kBias[2]).margin(1e-12));
  // random-constant model: p = r / N with r = 12^2 + 2^2 (range gradient is a unit vector)
  CHECK(last.var[0] == Approx((144.0 + 4.0) / 400).epsilon(1e-9));

  // After the switch: compensation with the frozen estimate.
  for (int k = 400; k < 460; ++k) {
    const double t = k;
    const Eigen::Vector3d p = truth_at(t);
    const prl_plot_t pl = plot_of(p, t, kBias, k);
    const auto out = est.process(pl, NavAtPlot{p, 2.0});
    const rnav::Polar q = rnav::polar_from_cartesian(p);
    REQUIRE(out.estimate.mode == kCompensating);
    CHECK_FALSE(out.estimate.has_chi);
    for (int i = 0; i < 3; ++i) {
      CHECK(out.estimate.eta[i] == last.eta[i]);  // no longer changes
      CHECK(out.estimate.var[i] == last.var[i]);
      CHECK(out.estimate.gain[i] == 0.0);
    }
    CHECK(out.compensated.range_m == Approx(q.range_m).margin(1e-9));
    CHECK(out.compensated.course_rad == Approx(q.course_rad).margin(1e-12));
    CHECK(out.compensated.glide_rad == Approx(q.glide_rad).margin(1e-12));
    CHECK(out.compensated.utime == pl.utime);
  }
}

TEST_CASE("switch time boundary: estimating strictly before switch_time_s", "[estimator]") {
  const PrlBiasOptions o = constant_bias_options();
  PrlBiasEstimator est(o, kEpoch);
  CHECK(est.estimating_at(utime_of(o.switch_time_s) - 1));
  CHECK_FALSE(est.estimating_at(utime_of(o.switch_time_s)));
}

TEST_CASE("compensate_during_estimation compensates from the first estimate on", "[estimator]") {
  PrlBiasOptions o = constant_bias_options();
  o.compensate_during_estimation = true;
  PrlBiasEstimator est(o, kEpoch);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d p = truth_at(k);
    const auto out = est.process(plot_of(p, k, kBias), NavAtPlot{p, 2.0});
    REQUIRE(out.estimate.mode == kEstimating);
    const rnav::Polar q = rnav::polar_from_cartesian(p);
    CHECK(out.compensated.range_m == Approx(q.range_m).margin(1e-9));
    CHECK(out.compensated.course_rad == Approx(q.course_rad).margin(1e-12));
    CHECK(out.compensated.glide_rad == Approx(q.glide_rad).margin(1e-12));
  }
}

TEST_CASE("course wrap: plot near +pi and nav near -pi give a small chi", "[estimator]") {
  PrlBiasEstimator est(constant_bias_options(), kEpoch);
  const double bias[3] = {6.0, -0.1 * kDegToRad, 0.15 * kDegToRad};
  // Aircraft behind the radar's x axis with course -pi + 0.0005 rad; a -0.1 deg bias pushes the
  // plot across the cut to +pi - 0.00125 rad.
  const Eigen::Vector3d p = rnav::cartesian_from_polar({10000, -M_PI + 0.0005, 0.03});
  const prl_plot_t pl = plot_of(p, 0, bias);
  REQUIRE(pl.course_rad > 3.0);
  REQUIRE(rnav::polar_from_cartesian(p).course_rad < -3.0);
  const auto out = est.process(pl, NavAtPlot{p, 2.0});
  CHECK(out.estimate.chi[1] == Approx(bias[1]).margin(1e-12));
  CHECK(out.estimate.eta[1] == Approx(bias[1]).margin(1e-12));
  // and the other way round: nav near +pi, plot near -pi
  const Eigen::Vector3d p2 = rnav::cartesian_from_polar({10000, M_PI - 0.0005, 0.03});
  const double bias2[3] = {6.0, 0.1 * kDegToRad, 0.15 * kDegToRad};
  PrlBiasEstimator est2(constant_bias_options(), kEpoch);
  const auto out2 = est2.process(plot_of(p2, 0, bias2), NavAtPlot{p2, 2.0});
  CHECK(out2.estimate.chi[1] == Approx(bias2[1]).margin(1e-12));

  // Compensation across the cut after the switch returns the true course in (-pi, pi].
  for (int k = 1; k < 10; ++k) est.process(plot_of(p, k, bias), NavAtPlot{p, 2.0});
  const prl_plot_t late = plot_of(p, 500, bias);
  const auto comp = est.process(late, std::nullopt);
  REQUIRE(comp.estimate.mode == kCompensating);
  CHECK(comp.compensated.course_rad == Approx(-M_PI + 0.0005).margin(1e-12));
  CHECK(comp.compensated.course_rad > -M_PI);
}

TEST_CASE("nav drop-out before the switch: NAV_DROPOUT and the plot is compensated",
          "[estimator]") {
  PrlBiasEstimator est(constant_bias_options(), kEpoch);
  // before any nav: no estimate, plot passes through
  {
    const prl_plot_t pl = plot_of(truth_at(0), 0, kBias);
    const auto out = est.process(pl, std::nullopt);
    CHECK(out.estimate.mode == kNoEstimate);
    CHECK_FALSE(out.estimate.has_chi);
    CHECK(out.compensated.range_m == pl.range_m);
    CHECK(out.compensated.course_rad == pl.course_rad);
  }
  prl_bias_estimate_t before{};
  for (int k = 1; k <= 30; ++k) {
    const Eigen::Vector3d p = truth_at(k);
    before = est.process(plot_of(p, k, kBias), NavAtPlot{p, 2.0}).estimate;
  }
  const Eigen::Vector3d p = truth_at(31);
  const prl_plot_t pl = plot_of(p, 31, kBias);
  const auto out = est.process(pl, std::nullopt);
  CHECK(out.estimate.mode == kNavDropout);
  CHECK_FALSE(out.estimate.has_chi);
  for (int i = 0; i < 3; ++i) {
    CHECK(out.estimate.eta[i] == before.eta[i]);
    CHECK(out.estimate.gain[i] == 0.0);
    CHECK(out.estimate.chi[i] == 0.0);
  }
  const rnav::Polar q = rnav::polar_from_cartesian(p);
  CHECK(out.compensated.range_m == Approx(q.range_m).margin(1e-9));
  CHECK(out.compensated.course_rad == Approx(q.course_rad).margin(1e-12));
  CHECK(out.compensated.glide_rad == Approx(q.glide_rad).margin(1e-12));
  // nav back: estimating again, the plot passes through
  const Eigen::Vector3d p2 = truth_at(32);
  const prl_plot_t pl2 = plot_of(p2, 32, kBias);
  const auto out2 = est.process(pl2, NavAtPlot{p2, 2.0});
  CHECK(out2.estimate.mode == kEstimating);
  CHECK(out2.compensated.range_m == pl2.range_m);

  est.reset();
  CHECK(est.process(pl2, std::nullopt).estimate.mode == kNoEstimate);
}

TEST_CASE("measurement variance: r1 from Table 1, plus the nav variance projected to polar",
          "[estimator]") {
  PrlBiasOptions o;
  PrlBiasEstimator est(o, kEpoch);
  // r1 = (2 sigma / 2)^2 per channel
  CHECK(est.r1()[0] == Approx(12.0 * 12.0).epsilon(1e-15));
  CHECK(est.r1()[1] == Approx(std::pow(0.25 * kDegToRad, 2)).epsilon(1e-14));
  CHECK(est.r1()[2] == Approx(std::pow(0.3 * kDegToRad, 2)).epsilon(1e-14));
  // First update: p = r = r1 + p2. For isotropic nav error sigma^2 I, the projected variances are
  // sigma^2 |grad|^2: |grad D| = 1, |grad Ek| = 1/h, |grad Eg| = 1/D (h = horizontal range).
  const double s = 2.5;
  const Eigen::Vector3d p(12000, 500, -3000);
  const double h = std::hypot(p.x(), p.z()), D = p.norm();
  const auto out = est.process(plot_of(p, 0, kBias), NavAtPlot{p, s});
  CHECK(out.estimate.var[0] == Approx(est.r1()[0] + s * s).epsilon(1e-12));
  CHECK(out.estimate.var[1] == Approx(est.r1()[1] + s * s / (h * h)).epsilon(1e-12));
  CHECK(out.estimate.var[2] == Approx(est.r1()[2] + s * s / (D * D)).epsilon(1e-12));

  o.add_nav_variance = false;
  PrlBiasEstimator est2(o, kEpoch);
  const auto out2 = est2.process(plot_of(p, 0, kBias), NavAtPlot{p, s});
  for (int i = 0; i < 3; ++i) CHECK(out2.estimate.var[i] == est2.r1()[i]);
}
