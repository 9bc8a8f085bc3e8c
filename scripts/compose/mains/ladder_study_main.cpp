// rnav_ladder_study: the injection ladder of the limits by injection (injected_limits.hpp) run
// on known hit curves instead of whole searches (ladder_curve.hpp): per curve, the injections
// it spends and the true rates at the sizes it states. Prints CSV on stdout, one row per curve
// and a last row "all" over every curve. docs/diagnosis.md quotes its default run.
//
// Options: one table below (rnav_ladder_study --help prints it). Exit status: 0 ok, 2 bad input,
// 1 other failure.
#include "common/io/cli.hpp"
#include "common/io/config.hpp"
#include "estimators/model_id/ladder_curve.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace {

using rnav::ConfigError;

// The 90 % points of the 500-plot landing flight's 19 parameters (scripts/bench --diagnose's
// flight), named and detected, in Fisher limits, as its diagnosis stated them.
const std::vector<rnav::HitCurve> kLandingCurves = {
    {4.8, 1.09, 1.09}, {4.8, 1.45, 1.09}, {4.8, 1.13, 1.13}, {4.8, 10.6, 1.03}, {4.8, 1.33, 1.18},
    {4.8, 1.03, 1.03}, {4.8, 1.45, 1.37}, {4.8, 1.09, 1.09}, {4.8, 1.28, 1.28}, {4.8, 1.19, 1.19},
    {4.8, 1.15, 1.15}, {4.8, 1.31, 1.31}, {4.8, 1.19, 1.19}, {4.8, 1.08, 1.08}, {4.8, 10.2, 1.49},
    {4.8, 0.18, 0.18}, {4.8, 0.16, 0.15}, {4.8, 1.48, 1.48}, {4.8, 1.11, 1.11}};

struct Options {
  std::vector<rnav::HitCurve> curves;
  double slope = 4.8, power = 0.9, band_lo = 0.8, band_hi = 0.97;
  int ladders = 400;
  long long seed = 1;
  rnav::InjectionOptions io;
};

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

rnav::cli::Parser make_parser(Options& a) {
  a.io.injections = 20;
  a.io.threads = 1;
  rnav::cli::Parser p(
      "rnav_ladder_study", "[--curve A_NAMED[:A_DETECTED]]... [options]",
      "The ladder of the limits by injection (rungs, fitted sizes and check batches, as rnav_diagnose runs them) on "
      "known probit hit curves P(hit | a) = Phi(slope log(a / a90) + z_power) instead of whole searches: per curve, "
      "the injections spent and the true rates at the stated sizes. Prints CSV on stdout: "
      "a_named,a_detected,slope,ladders,injections_mean,named_rate_mean,named_rate_sd,named_in_band,"
      "detected_rate_mean,detected_rate_sd,detected_in_band; a last row 'all' over every curve.");
  p.repeated("--curve", "A_NAMED[:A_DETECTED]",
             "a curve's 90 % points [Fisher limits, the ladder's first size], > 0, A_DETECTED <= A_NAMED (default: "
             "A_DETECTED = A_NAMED; without --curve, the 19 parameters of the 500-plot landing flight)",
             [&a](const std::string& v) {
               const auto colon = v.find(':');
               rnav::HitCurve k;
               k.a_named = rnav::cli::number("--curve", v.substr(0, colon), 1e-6, 1e6);
               k.a_detected = colon == std::string::npos ? k.a_named : rnav::cli::number("--curve", v.substr(colon + 1), 1e-6, 1e6);
               if (k.a_detected > k.a_named)
                 throw ConfigError("--curve " + v + ": the detected size must not exceed the named one (named implies detected)");
               a.curves.push_back(k);
             })
      .value("--slope", "B", "probit slope in log a of --curve's curves, (0, 100]", "4.8",
             [&a](const std::string& v) { a.slope = rnav::cli::number("--slope", v, 1e-9, 100); })
      .value("--ladders", "N", "ladders per curve, 1 .. 1000000", "400",
             [&a](const std::string& v) { a.ladders = static_cast<int>(rnav::parse_integer("--ladders", v, 1, 1000000)); })
      .value("--seed", "S", "seed of the first ladder (ladder j of every curve: S + j), an integer >= 0", "1",
             [&a](const std::string& v) { a.seed = rnav::parse_integer("--seed", v, 0, (1LL << 62)); })
      .value("--ladder-injections", "N", "injections per ladder size (rnav_diagnose's), 1 .. 1000", "10",
             [&a](const std::string& v) { a.io.ladder_injections = static_cast<int>(rnav::parse_integer("--ladder-injections", v, 1, 1000)); })
      .value("--injections", "N", "injections per check batch (rnav_diagnose's), 1 .. 1000", "20",
             [&a](const std::string& v) { a.io.injections = static_cast<int>(rnav::parse_integer("--injections", v, 1, 1000)); })
      .value("--power", "P", "the rate the limits are stated at, (0.5, 1)", "0.9",
             [&a](const std::string& v) { a.power = rnav::cli::number("--power", v, 0.5 + 1e-9, 1 - 1e-9); })
      .value("--band", "LO:HI", "the in_band columns: the share of stated sizes whose true rate lies in [LO, HI], 0 <= LO < HI <= 1",
             "0.8:0.97", [&a](const std::string& v) {
               const auto colon = v.find(':');
               if (colon == std::string::npos) throw ConfigError("--band " + v + ": expected LO:HI");
               a.band_lo = rnav::cli::number("--band", v.substr(0, colon), 0, 1);
               a.band_hi = rnav::cli::number("--band", v.substr(colon + 1), 0, 1);
               if (!(a.band_lo < a.band_hi)) throw ConfigError("--band " + v + ": LO must be below HI");
             })
      .epilog(
          "Sizes in Fisher limits; rates are the curve's true hit probabilities at the stated sizes (a ladder that\n"
          "states no size counts 0). Deterministic: the same options give the same table.\n"
          "Exit status: 0 ok, 2 bad input, 1 other failure.");
  return p;
}

// Running mean and SD of one column, and its share in the band.
struct Column {
  double sum = 0, sum2 = 0, in = 0, n = 0;
  void add(double x, double lo, double hi) { sum += x, sum2 += x * x, in += x >= lo && x <= hi, n += 1; }
  std::string text() const {
    const double m = sum / n;
    return num(m) + "," + num(std::sqrt(std::max(0.0, sum2 / n - m * m))) + "," + num(in / n);
  }
};

}  // namespace

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_ladder_study", [&]() -> int {
    Options a;
    rnav::cli::Parser p = make_parser(a);
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (a.curves.empty()) a.curves = kLandingCurves;
    else
      for (auto& k : a.curves) k.slope = a.slope;
    std::cout << "a_named,a_detected,slope,ladders,injections_mean,named_rate_mean,named_rate_sd,named_in_band,"
                 "detected_rate_mean,detected_rate_sd,detected_in_band\n";
    Column all_named, all_detected;
    double all_injections = 0;
    for (const rnav::HitCurve& k : a.curves) {
      Column named, detected;
      double injections = 0;
      for (int j = 0; j < a.ladders; ++j) {
        const rnav::LadderOutcome o = rnav::ladder_on_curve(k, a.power, a.io, static_cast<std::uint64_t>(a.seed + j));
        named.add(o.named_rate, a.band_lo, a.band_hi), all_named.add(o.named_rate, a.band_lo, a.band_hi);
        detected.add(o.detected_rate, a.band_lo, a.band_hi), all_detected.add(o.detected_rate, a.band_lo, a.band_hi);
        injections += o.injections, all_injections += o.injections;
      }
      std::cout << num(k.a_named) << "," << num(k.a_detected) << "," << num(k.slope) << "," << a.ladders << ","
                << num(injections / a.ladders) << "," << named.text() << "," << detected.text() << "\n";
    }
    std::cout << "all,all,," << a.ladders * static_cast<int>(a.curves.size()) << "," << num(all_injections / all_named.n) << ","
              << all_named.text() << "," << all_detected.text() << "\n";
    return 0;
  });
}
