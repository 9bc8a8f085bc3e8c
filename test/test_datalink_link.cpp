// Unit tests of the navigation data link's budget (sim/datalink/link_budget.hpp,
// nav_link.hpp): reference values computed by hand, the equations' scalings, the loss rate
// drawn against the configured SNR curve (binomial band), and the scenario keys' validation.
#include "sim/datalink/code_family.hpp"
#include "common/io/config.hpp"
#include "test/config_error.hpp"
#include "sim/datalink/link_budget.hpp"
#include "sim/datalink/nav_link.hpp"
#include "common/physics/random.hpp"
#include "scripts/compose/scenario/scenario.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace dl = rnav::datalink;
using Catch::Contains;
using nlohmann::json;
using rnav_test::config_error;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string scenario_error(const std::string& text) {
  return config_error([&] { rnav::Scenario::from_json(json::parse(text)); });
}

}  // namespace

TEST_CASE("free-space loss at 10 km and 1 GHz is 112.448 dB as computed by hand", "[datalink][budget]") {
  // (4 pi d f / c)^2 with d = 1e4 m, f = 1e9 Hz, c = 299 792 458 m/s:
  // 4 pi 1e13 / 299792458 = 419 169.0, 20 log10(419 169.0) = 112.4478 dB; the textbook rule
  // 20 log10(d / km) + 20 log10(f / MHz) + 32.4478 gives 20 + 60 + 32.4478 = 112.4478 dB.
  CHECK(dl::to_db(dl::free_space_loss(1e4, 1e9)) == Approx(112.4478).margin(1e-4));
  // 1/d^2 and 1/lambda^2: doubling either adds 6.0206 dB.
  CHECK(dl::to_db(dl::free_space_loss(2e4, 1e9)) - dl::to_db(dl::free_space_loss(1e4, 1e9)) == Approx(6.0206).margin(1e-4));
  CHECK(dl::to_db(dl::free_space_loss(1e4, 2e9)) - dl::to_db(dl::free_space_loss(1e4, 1e9)) == Approx(6.0206).margin(1e-4));
  CHECK_THROWS_WITH(dl::free_space_loss(-1, 1e9), Contains("range_m"));
  CHECK_THROWS_WITH(dl::free_space_loss(1e3, 0), Contains("frequency_hz"));
}

TEST_CASE("BPSK bit error rate at Eb/N0 = 9.6 dB is 1e-5 and the message loss compounds it", "[datalink][budget]") {
  // erfc(sqrt(10^0.96)) / 2 = 9.736e-6: the textbook "1e-5 at 9.6 dB" for coherent BPSK.
  const double ber = dl::ber_bpsk(dl::from_db(9.6));
  CHECK(ber == Approx(9.736e-6).epsilon(1e-3));
  CHECK(ber == Approx(1e-5).epsilon(0.03));
  CHECK(dl::q_function(0) == Approx(0.5));
  CHECK(dl::q_function(1.959963985) == Approx(0.025).epsilon(1e-6));
  CHECK(dl::ber_bpsk(0) == Approx(0.5));                       // no signal: a coin toss
  CHECK(dl::ber_bpsk(std::numeric_limits<double>::infinity()) == 0);
  // 1 - (1 - 1e-3)^256 = 0.225957; a tiny BER stays exact: 1 - (1 - 1e-12)^256 = 2.56e-10.
  CHECK(dl::message_loss(1e-3, 256) == Approx(0.2259572).epsilon(1e-6));
  CHECK(dl::message_loss(1e-12, 256) == Approx(2.56e-10).epsilon(1e-9));
  CHECK(dl::message_loss(0, 256) == 0);
  CHECK(dl::message_loss(0.5, 1) == Approx(0.5));
  CHECK_THROWS_WITH(dl::ber_bpsk(-1), Contains("ebn0"));
  CHECK_THROWS_WITH(dl::message_loss(1.5, 8), Contains("ber"));
  CHECK_THROWS_WITH(dl::message_loss(0.1, 0), Contains("bits"));
}

TEST_CASE("link budget: SNR and Eb/N0 against the budget added up in dB by hand", "[datalink][budget]") {
  rnav::DatalinkOptions p;
  p.peak_power_w = 2.0;
  p.frequency_hz = 1.2e9;
  p.tx_gain_dbi = 1.5;
  p.rx_gain_dbi = 4.0;
  p.noise_figure_db = 6.0;
  p.noise_temperature_k = 290;
  p.system_loss_db = 7.0;
  p.chip_rate_hz = 5e6;
  p.bandwidth_chips = 0.75;
  p.code_length = 511;
  p.message_bits = 200;
  const dl::LinkBudget b(p, 1.8);
  const double d = 25e3;
  // P_mean = 2 / 1.8^2 = 0.617284 W = -2.0952 dBW.
  const double p_mean_dbw = 10 * std::log10(2.0 / (1.8 * 1.8));
  CHECK(b.mean_power_w() == Approx(0.6172840).epsilon(1e-6));
  // FSPL = 20 log10(4 pi d f / c); k T0 = -203.9762 dBW/Hz at 290 K; B_n = 2 * 0.75 * 5e6 = 7.5 MHz.
  const double fspl_db = 20 * std::log10(4 * kPi * d * p.frequency_hz / 299792458.0);
  const double kt0_dbw_hz = 10 * std::log10(1.380649e-23 * 290);
  CHECK(kt0_dbw_hz == Approx(-203.9762).margin(1e-4));
  const double c_dbw = p_mean_dbw + 1.5 + 4.0 - fspl_db - 7.0;
  const double n_dbw = kt0_dbw_hz + 6.0 + 10 * std::log10(7.5e6);
  CHECK(b.noise_bandwidth_hz() == Approx(7.5e6));
  CHECK(dl::to_db(b.received_power_w(d)) == Approx(c_dbw).margin(1e-9));
  CHECK(dl::to_db(b.snr(d)) == Approx(c_dbw - n_dbw).margin(1e-9));
  // Despreading: R_b = 5e6 / 511 bit/s, G_p = 2 B N = 766.5; Eb/N0 = C / (k T0 F R_b).
  CHECK(b.bit_rate_bps() == Approx(5e6 / 511));
  CHECK(b.processing_gain() == Approx(766.5));
  const double ebn0_db = c_dbw - (kt0_dbw_hz + 6.0 + 10 * std::log10(5e6 / 511));
  CHECK(dl::to_db(b.ebn0(d)) == Approx(ebn0_db).margin(1e-9));
  CHECK(b.p_loss(d) == Approx(dl::message_loss(dl::ber_bpsk(dl::from_db(ebn0_db)), 200)).epsilon(1e-9));
}

TEST_CASE("link budget: the peak factor costs PF^2 of mean power and p_loss grows with range", "[datalink][budget]") {
  rnav::DatalinkOptions p;  // the defaults
  p.peak_power_w = 0.05;
  const dl::LinkBudget flat(p, 1.0);
  const dl::LinkBudget peaky(p, 2.0);
  // Eb/N0 ~ P_peak / (PF^2 d^2): PF 2 at d is PF 1 at 2 d (6.02 dB).
  for (double d : {3e3, 12e3, 40e3}) {
    CHECK(peaky.ebn0(d) == Approx(flat.ebn0(2 * d)).epsilon(1e-12));
    CHECK(peaky.p_loss(d) == Approx(flat.p_loss(2 * d)).epsilon(1e-9));
  }
  double last = -1;
  for (double d = 1e3; d < 1e6; d *= 1.3) {
    CHECK(flat.p_loss(d) >= last);
    last = flat.p_loss(d);
  }
  for (double q : {0.01, 0.5, 0.99}) CHECK(flat.p_loss(flat.range_for_p_loss(q)) == Approx(q).epsilon(1e-8));
  CHECK(flat.range_for_p_loss(0.5) == Approx(2 * peaky.range_for_p_loss(0.5)).epsilon(1e-9));
}

TEST_CASE("link budget: bad parameters throw ConfigError naming them", "[datalink][budget][input]") {
  const auto error = [](auto set, double peak_factor = 1.8) {
    rnav::DatalinkOptions p;
    set(p);
    return config_error([&] { dl::LinkBudget b(p, peak_factor); });
  };
  CHECK_THAT(error([](auto& p) { p.peak_power_w = -1; }), Contains("peak_power_w"));
  CHECK_THAT(error([](auto& p) { p.peak_power_w = 0; }), Contains("peak_power_w"));
  CHECK_THAT(error([](auto& p) { p.peak_power_w = std::nan(""); }), Contains("peak_power_w"));
  CHECK_THAT(error([](auto&) {}, 0.9), Contains("peak_factor"));
  CHECK_THAT(error([](auto&) {}, std::nan("")), Contains("peak_factor"));
  CHECK_THAT(error([](auto& p) { p.frequency_hz = std::numeric_limits<double>::infinity(); }), Contains("frequency_hz"));
  CHECK_THAT(error([](auto& p) { p.noise_figure_db = -1; }), Contains("noise_figure_db"));
  CHECK_THAT(error([](auto& p) { p.system_loss_db = std::nan(""); }), Contains("system_loss_db"));
  CHECK_THAT(error([](auto& p) { p.bandwidth_chips = 0; }), Contains("bandwidth_chips"));
  CHECK_THAT(error([](auto& p) { p.message_bits = 0; }), Contains("message_bits"));
  CHECK(error([](auto&) {}) == "<no exception>");
}

TEST_CASE("the link's peak factor is the code study's median: Gold 1.806 and ab2-phase 15 % lower at rc 0.5 0.25",
          "[datalink][budget]") {
  // README, code-study table, N = 127, raised cosine B = 0.5, beta = 0.25: Gold median 1.806,
  // ab2-phase -14.9 %, ab2 +0.3 % (129 codes, 24 samples per chip, as the defaults here).
  rnav::DatalinkOptions d;
  CHECK(dl::datalink_peak_factor(d) == Approx(1.806).margin(0.0005));
  d.family = "ab2-phase";
  CHECK(dl::datalink_peak_factor(d) / 1.806 - 1 == Approx(-0.149).margin(0.0015));
  d.family = "ab2";
  CHECK(dl::datalink_peak_factor(d) / 1.806 - 1 == Approx(0.003).margin(0.0015));
  // The worst code (quantile 1) is above the median; unfiltered BPSK has PF 1 for every code.
  d.family = "gold";
  d.pf_quantile = 1;
  CHECK(dl::datalink_peak_factor(d) > 1.806);
  CHECK(dl::family_peak_factor("gold", 127, dl::Filter::none(), 0.5, 129, 24) == Approx(1.0));
}

TEST_CASE("observed message loss at fixed ranges lies in the binomial band of the configured p_loss",
          "[datalink][statistics]") {
  // A link whose p_loss passes 0.1, 0.5 and 0.9 at ranges found from the model; n messages are
  // drawn at each through NavLink::lost with one fixed stream. The observed fraction k/n has
  // standard error sqrt(p (1 - p) / n); we accept |k/n - p| <= z SE with z from a Bonferroni
  // split of a familywise false-alarm rate of 1e-5 over the ranges tested (z = 4.65 for 3: the
  // normal approximation is good here, n p (1 - p) >= 3600). The band is narrow enough to fail a
  // model 20 % off: checked below for each range, by rejecting 0.8 p and min(1.2 p, 1).
  constexpr int kRangesTested = 3;
  constexpr double kFamilywiseAlpha = 1e-5;
  constexpr int n = 40000;
  // z with P(|Z| > z) = alpha / K: the two-sided normal quantile, by bisection on erfc.
  double lo = 0, hi = 10;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > kFamilywiseAlpha / kRangesTested ? lo : hi) = mid;
  }
  const double z = lo;
  CHECK(z == Approx(4.65).margin(0.01));

  rnav::DatalinkOptions p;
  p.peak_power_w = 0.02;
  const dl::NavLink link(dl::LinkBudget(p, 1.8), rnav::Geodetic{48.1, 16.57, 232});
  const double targets[kRangesTested] = {0.1, 0.5, 0.9};
  rnav::Rng rng(7, 0, rnav::Stream::kTest);
  for (double target : targets) {
    const double d = link.budget().range_for_p_loss(target);
    const double pl = link.budget().p_loss(d);
    long k = 0;
    for (int i = 0; i < n; ++i) k += link.lost(d, rng.uniform()) ? 1 : 0;
    const double frac = static_cast<double>(k) / n, band = z * std::sqrt(pl * (1 - pl) / n);
    INFO("range " << d << " m: p_loss " << pl << ", observed " << frac << ", band +-" << band);
    CHECK(std::abs(frac - pl) <= band);
    CHECK(std::abs(frac - 0.8 * pl) > band);                // a model 20 % low would fail
    CHECK(std::abs(frac - std::min(1.2 * pl, 1.0)) > band);  // and one 20 % high
  }
}

TEST_CASE("scenario datalink keys: defaults, unknown key, negative power and NaN name the key", "[datalink][config]") {
  const rnav::Scenario sc = rnav::Scenario::from_json(json::object());
  CHECK_FALSE(sc.datalink.enabled);
  CHECK(sc.datalink.family == "gold");
  CHECK(sc.datalink.code_length == 127);
  CHECK(sc.datalink.peak_power_w == 1.0);
  CHECK_THAT(scenario_error(R"({"datalink": {"peak_power": 1}})"),
             Contains("datalink.peak_power (did you mean 'datalink.peak_power_w'?)"));
  CHECK_THAT(scenario_error(R"({"datalink": {"peak_power_w": -1}})"), Contains("datalink.peak_power_w"));
  CHECK_THAT(scenario_error(R"({"datalink": {"peak_power_w": 0}})"), Contains("datalink.peak_power_w"));
  CHECK_THAT(scenario_error(R"({"datalink": {"frequency_hz": "NaN"}})"), Contains("datalink.frequency_hz"));
  CHECK_THAT(scenario_error(R"({"datalink": {"family": "glod"}})"), Contains("did you mean 'gold'?"));
  CHECK_THAT(scenario_error(R"({"datalink": {"filter": "raised"}})"), Contains("datalink.filter"));
  CHECK_THAT(scenario_error(R"({"datalink": {"code_length": 255}})"), Contains("datalink.code_length"));
  CHECK_THAT(scenario_error(R"({"datalink": {"enabled": 1}})"), Contains("datalink.enabled"));
  CHECK_THAT(scenario_error(R"({"datalink": {"pf_codes": 200}})"), Contains("datalink.pf_codes"));
  // A message longer than the link period: 100000 bits * 127 chips / 10.16e6 chips/s = 1.25 s > 0.5 s.
  CHECK_THAT(scenario_error(R"({"datalink": {"message_bits": 100000}})"), Contains("datalink.message_bits"));
  CHECK_THAT(scenario_error(R"({"datalink": {"filter": "rc", "bandwidth_chips": 10, "samples_per_chip": 16}})"),
             Contains("datalink.samples_per_chip"));
  CHECK(scenario_error(R"({"datalink": {"enabled": true, "family": "ab2-phase", "peak_power_w": 0.01}})") ==
        "<no exception>");
}
