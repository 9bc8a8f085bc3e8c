// The UAV sensor's bearing error model: the nominal white noise, and the diagnosis catalogue's
// effects it can inject (sensor_effects.*), each checked against its definition; a nominal
// model's random stream is unchanged by the catalogue being available.
#include <catch2/catch.hpp>

#include "sim/uav/bearing_error_model.hpp"
#include "test/stat_bands.hpp"

#include <cmath>

using namespace rnav;
using namespace rnav_test;

namespace {

constexpr int kN = 20000;
constexpr double kDt = 0.2;

BearingTruth truth_at(int k) {
  BearingTruth t;
  t.t_s = kDt * k;
  t.bearing_rad = 0.01 * k;
  t.range_m = 300;
  t.bearing_rate_radps = 0.0667 + 0.01 * std::sin(0.05 * k);  // a circling observer, slightly varying
  return t;
}

std::vector<double> errors(const SensorEffectsOptions& fx, std::uint64_t seed) {
  SensorOptions so;  // sigma 0.5 deg
  BearingErrorModel m(so, fx);
  Rng rng(seed, 0, Stream::kTest);
  m.start(rng);
  std::vector<double> e;
  for (int k = 0; k < kN; ++k) e.push_back(m.error(truth_at(k), rng));
  return e;
}

const double kSigma = 0.5 * kDegToRad;

}  // namespace

TEST_CASE("bearing error: nominal white noise has sigma_deg and zero mean", "[bearing_error]") {
  const auto e = errors({}, 1);
  CHECK(variance_ratio_band(kN).contains(mean_square_about(e, 0) / (kSigma * kSigma)));
  CHECK(std::abs(mean(e)) < kZ999 * kSigma / std::sqrt(kN));
}

TEST_CASE("bearing error: deterministic effects add exactly b - beta_dot tau + d t + A sin(2 pi t / P)",
          "[bearing_error]") {
  SensorEffectsOptions fx;
  fx.bearing_bias_rad = 0.003;
  fx.time_offset_s = 0.05;
  fx.bias_drift_radps = 1e-5;
  fx.periodic_period_s = 30;
  fx.periodic_amplitude_rad = 0.002;
  const auto nominal = errors({}, 2), with = errors(fx, 2);  // same seed: the same noise draws
  for (int k = 0; k < kN; k += 997) {
    const auto t = truth_at(k);
    const double expect = 0.003 - t.bearing_rate_radps * 0.05 + 1e-5 * t.t_s + 0.002 * std::sin(2 * M_PI * t.t_s / 30);
    CHECK(with[k] - nominal[k] == Approx(expect).margin(1e-12));
  }
}

TEST_CASE("bearing error: noise_scale multiplies the sigma", "[bearing_error]") {
  SensorEffectsOptions fx;
  fx.noise_scale = 2.5;
  const auto e = errors(fx, 3);
  CHECK(variance_ratio_band(kN).contains(mean_square_about(e, 0) / std::pow(2.5 * kSigma, 2)));
}

TEST_CASE("bearing error: correlated_noise is Gauss-Markov with the stated correlation time", "[bearing_error]") {
  SensorEffectsOptions fx;
  fx.correlated_noise_tau_s = 2.0;
  const auto e = errors(fx, 4);
  std::vector<double> a(e.begin(), e.end() - 1), b(e.begin() + 1, e.end());
  const double rho = std::exp(-kDt / 2.0);
  // SE of a lag-1 autocorrelation of an AR(1) series: sqrt((1 - rho^2) / n)
  CHECK(std::abs(correlation(a, b) - rho) < kZ999 * std::sqrt((1 - rho * rho) / kN));
  // the marginal sigma stays sigma_deg; the effective dof of the variance is n (1 - rho^2) / (1 + rho^2)
  const double dof = kN * (1 - rho * rho) / (1 + rho * rho);
  CHECK(variance_ratio_band(dof).contains(mean_square_about(e, 0) / (kSigma * kSigma)));
}

TEST_CASE("bearing error: outliers occur with the stated probability", "[bearing_error]") {
  SensorEffectsOptions fx;
  fx.outlier_prob = 0.02;
  fx.outlier_scale = 10;
  const auto e = errors(fx, 5);
  // |e| > 5 sigma: nominal frames almost never (5.7e-7); an outlier frame's error is
  // N(0, (1 + 100) sigma^2), beyond 5 sigma with probability erfc(5 / sqrt(2 * 101)).
  int n = 0;
  for (double x : e) n += std::abs(x) > 5 * kSigma;
  const double p = 0.02 * std::erfc(5 / std::sqrt(2.0 * 101)) + 0.98 * std::erfc(5 / std::sqrt(2.0));
  CHECK(std::abs(n - kN * p) < kZ999 * std::sqrt(kN * p * (1 - p)));
}

TEST_CASE("bearing error: effects left at their defaults draw nothing extra", "[bearing_error]") {
  // A nominal run keeps the random stream it always had: defaults give the white noise alone.
  SensorOptions so;
  BearingErrorModel m(so);
  Rng a(9, 0, Stream::kTest), b(9, 0, Stream::kTest);
  m.start(a);
  for (int k = 0; k < 100; ++k) CHECK(m.error(truth_at(k), a) == kSigma * b.normal());
}
