// rnav_code_study: peak factor and correlation peaks of Gold codes and of nonlinear noise-like
// (AB, Bernoulli-map) codes after band-limiting. Prints CSV on stdout:
//   per code (default):  family,length,filter,bandwidth,rolloff,code,peak_factor,max_auto_offpeak,max_cross
//   --spectrum:          family,length,filter,bandwidth,rolloff,f_over_rc,psd_db
// scripts/code_study runs it and writes the table and plots.
//
// Options: one table below (rnav_code_study --help prints it). Exit status: 0 ok, 2 bad input,
// 1 other failure.
#include "sim/datalink/ab_codes.hpp"
#include "common/io/cli.hpp"
#include "sim/datalink/code_family.hpp"
#include "sim/datalink/code_metrics.hpp"
#include "common/io/config.hpp"
#include "sim/datalink/gold.hpp"
#include "sim/datalink/waveform.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using rnav::ConfigError;
namespace dl = rnav::datalink;

const std::vector<std::string> kDefaultFamilies = {"gold", "ab2", "ab3", "ab2-phase", "gold-qpsk"};
const std::vector<std::string> kDefaultFilters = {"none",    "brick:0.5", "brick:0.75",   "brick:1",      "brick:1.5",
                                                  "brick:2", "brick:3",   "rc:0.5:0.25", "rc:0.5:0.5", "rc:0.5:1"};

std::string num(double x) {
  if (std::isinf(x)) return "inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

// What the command line sets.
struct Options {
  std::vector<std::string> families, filter_texts;
  std::vector<int> lengths;
  int codes_per_family = 129, partners = 16, samples_per_chip = 24;
  long long seed = 1;
  bool spectrum = false;
  double spectrum_max_f = 4.0;
};

// The option table of rnav_code_study (--help prints it in this order), setting a.
rnav::cli::Parser make_parser(Options& a) {
  rnav::cli::Parser p(
      "rnav_code_study", "[--family NAME]... [--length N]... [--filter SPEC]... [options]",
      "Peak factor (peak-to-RMS) of band-limited BPSK waveforms of Gold codes and of nonlinear noise-like codes from "
      "the Bernoulli (doubling) map and its relatives (sim/datalink/ab_codes.hpp), with each code's periodic "
      "auto- and cross-correlation peaks. Prints CSV on stdout, one row per family, length, filter and code: "
      "family,length,filter,bandwidth,rolloff,code,peak_factor,max_auto_offpeak,max_cross; with --spectrum, the "
      "family-mean power spectrum instead: family,length,filter,bandwidth,rolloff,f_over_rc,psd_db.");
  p.repeated("--family", "NAME",
             "code family: gold (Gold codes of a preferred pair), gold-qpsk (two Gold codes as I and Q), "
             "abR (the map x -> R x mod 1, R = 2..16, chip sgn cos 2 pi x), tent (tent map, same chip), abR-phase / "
             "tent-phase (chip exp(2 pi i x)) (default gold, ab2, ab3, ab2-phase, gold-qpsk; tent gives the same binary codes as ab2, see ab_codes.hpp)",
             [&a](const std::string& v) {
               if (v != "gold" && v != "gold-qpsk") {
                 try {
                   dl::AbSpec::parse(v);
                 } catch (const std::invalid_argument&) {
                   throw ConfigError("--family '" + v + "': not gold, gold-qpsk, abR (R = 2..16), tent, or abR/tent with -phase");
                 }
               }
               a.families.push_back(v);
             })
      .repeated("--length", "N", "code length [chips]: 127, 511 or 1023 (default all three)",
                [&a](const std::string& v) {
                  const int n = static_cast<int>(rnav::parse_integer("--length", v, 1, 1 << 24));
                  if (n != 127 && n != 511 && n != 1023)
                    throw ConfigError("--length " + std::to_string(n) + ": must be 127, 511 or 1023 (the Gold lengths with a stored preferred pair)");
                  a.lengths.push_back(n);
                })
      .repeated("--filter", "SPEC",
                "band-limiting filter: none, brick:B (ideal low-pass, |f| <= B), rc:B:BETA (raised cosine, "
                "-6 dB at B, roll-off BETA in (0, 1]); B in chip rates, (0, 1000] (default none, brick:0.5, brick:0.75, "
                "brick:1, brick:1.5, brick:2, brick:3, rc:0.5:0.25, rc:0.5:0.5, rc:0.5:1)",
                [&a](const std::string& v) {
                  try {
                    dl::Filter::parse(v);
                  } catch (const std::invalid_argument& e) {
                    throw ConfigError(std::string("--filter ") + e.what());
                  }
                  a.filter_texts.push_back(v);
                })
      .value("--codes", "M", "codes per family and length, 2 .. 100000 (Gold: at most N+2, spread evenly over the family; AB: seeds SEED .. SEED+M-1)",
             "129", [&a](const std::string& v) { a.codes_per_family = static_cast<int>(rnav::parse_integer("--codes", v, 2, 100000)); })
      .value("--partners", "K", "cross-correlation partners per code: the K codes after it (cyclically) in its family's set, 1 .. M-1",
             "16", [&a](const std::string& v) { a.partners = static_cast<int>(rnav::parse_integer("--partners", v, 1, 100000)); })
      .value("--seed", "S", "first seed of the AB families, an integer >= 0", "1",
             [&a](const std::string& v) { a.seed = rnav::parse_integer("--seed", v, 0, (1LL << 62)); })
      .value("--samples-per-chip", "S", "samples per chip of the waveform, 2 .. 256; every filter's band edge must be below S/2 chip rates. 24 puts "
             "the Gibbs peaks of brick walls at B = 0.5, 0.75, 1, 1.5, 2, 3 (t = 1/(2B) after a chip edge) on the grid; "
             "peak factors then agree with S = 96 to 0.1 %",
             "24", [&a](const std::string& v) { a.samples_per_chip = static_cast<int>(rnav::parse_integer("--samples-per-chip", v, 2, 256)); })
      .flag("--spectrum", "print the family-mean power spectrum instead of per-code rows", a.spectrum)
      .value("--spectrum-max-f", "F", "with --spectrum: the highest frequency printed [chip rates], > 0", "4",
             [&a](const std::string& v) { a.spectrum_max_f = rnav::cli::number("--spectrum-max-f", v, 1e-9, 1e6); })
      .epilog(
          "Units: time in chips T = 1/Rc, frequency in chip rates Rc. peak_factor = max|s| / rms(s) of the waveform\n"
          "(dimensionless); max_auto_offpeak = max over shifts != 0 of |periodic autocorrelation| and max_cross = max over\n"
          "shifts and partners of |periodic cross-correlation|, both in chip products (a Gold code of degree n: t(n)).\n"
          "psd_db: power per chip rate of bandwidth relative to the chip power, 10 log10(N P_m), family mean.\n"
          "Exit status: 0 ok, 2 bad input, 1 other failure.");
  return p;
}

// The defaults of what was not given, set into a; the options checked against each other;
// returns the filters.
std::vector<dl::Filter> complete_options(Options& a) {
  if (a.families.empty()) a.families = kDefaultFamilies;
  if (a.lengths.empty()) a.lengths = {127, 511, 1023};
  if (a.filter_texts.empty()) a.filter_texts = kDefaultFilters;
  const int M = a.codes_per_family;
  if (a.partners > M - 1) throw ConfigError("--partners " + std::to_string(a.partners) + " must be below --codes " + std::to_string(M));
  std::vector<dl::Filter> filters;
  for (const auto& t : a.filter_texts) {
    filters.push_back(dl::Filter::parse(t));
    if (!(filters.back().band_edge() < 0.5 * a.samples_per_chip) && filters.back().kind() != dl::Filter::Kind::none)
      throw ConfigError("--filter " + t + ": its band edge must be below --samples-per-chip / 2 = " + num(0.5 * a.samples_per_chip) +
                        " chip rates");
  }
  for (const auto& f : a.families)
    for (int N : a.lengths)
      if ((f == "gold" || f == "gold-qpsk") && M > N + 2)
        throw ConfigError("--codes " + std::to_string(M) + " exceeds the Gold family size N+2 = " + std::to_string(N + 2) +
                          " at --length " + std::to_string(N));
  return filters;
}

// Each of the M codes' largest off-peak periodic autocorrelation, and its largest
// cross-correlation with the `partners` codes after it (cyclically) [chip products].
void correlation_peaks(const std::vector<dl::FamilyCode>& codes, int M, int partners, std::vector<double>& auto_peak,
                       std::vector<double>& cross_peak) {
  std::vector<dl::Signal> chips;
  for (const auto& c : codes) chips.push_back(c.chips);
  const dl::CorrelationBank bank(chips);
  for (int i = 0; i < M; ++i) {
    auto_peak[static_cast<std::size_t>(i)] = bank.max_offpeak_auto(i);
    double m = 0;
    for (int d = 1; d <= partners; ++d) m = std::max(m, bank.max_cross(i, (i + d) % M));
    cross_peak[static_cast<std::size_t>(i)] = m;
  }
}

// The rows of one family, length N and filter: per code, or with --spectrum the family-mean
// power spectrum.
void print_rows(const Options& a, const std::string& family, int N, const std::vector<dl::FamilyCode>& codes,
                const dl::Filter& filter, const std::vector<double>& auto_peak, const std::vector<double>& cross_peak) {
  const std::string head = family + "," + std::to_string(N) + "," + filter.name() + "," + num(filter.bandwidth()) + "," +
                           num(filter.rolloff()) + ",";
  std::vector<double> mean_power;
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const dl::Signal w = dl::bpsk_waveform(codes[i].chips, a.samples_per_chip, filter);
    if (a.spectrum) {
      const auto ps = dl::power_spectrum(w);
      if (mean_power.empty()) mean_power.assign(ps.size(), 0.0);
      for (std::size_t q = 0; q < ps.size(); ++q) mean_power[q] += ps[q] / static_cast<double>(codes.size());
      continue;
    }
    std::cout << head << codes[i].index << "," << num(dl::peak_factor(w)) << "," << num(auto_peak[i]) << ","
              << num(cross_peak[i]) << "\n";
  }
  if (a.spectrum) {
    // Harmonic q of the period N T is at f = q / N chip rates; psd = N P_q (power per chip rate).
    for (std::size_t q = 0; q < mean_power.size() / 2 && static_cast<double>(q) / N <= a.spectrum_max_f; ++q) {
      const double psd = static_cast<double>(N) * mean_power[q];
      std::cout << head << num(static_cast<double>(q) / N) << "," << num(psd > 0 ? 10 * std::log10(psd) : -400.0) << "\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_code_study", [&]() -> int {
    Options a;
    rnav::cli::Parser p = make_parser(a);
    if (!p.parse(argc, argv, std::cout)) return 0;
    const std::vector<dl::Filter> filters = complete_options(a);
    const int M = a.codes_per_family;

    std::cout << (a.spectrum ? "family,length,filter,bandwidth,rolloff,f_over_rc,psd_db\n"
                             : "family,length,filter,bandwidth,rolloff,code,peak_factor,max_auto_offpeak,max_cross\n");
    for (const auto& family : a.families) {
      for (int N : a.lengths) {
        const auto codes = dl::family_codes(family, N, M, static_cast<std::uint64_t>(a.seed));
        std::vector<double> auto_peak(codes.size()), cross_peak(codes.size());
        if (!a.spectrum) correlation_peaks(codes, M, a.partners, auto_peak, cross_peak);
        for (const auto& filter : filters) print_rows(a, family, N, codes, filter, auto_peak, cross_peak);
        std::cout.flush();
      }
    }
    return 0;
  });
}
