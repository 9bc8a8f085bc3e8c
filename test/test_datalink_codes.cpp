// Unit tests of sim/datalink's codes library: m-sequence period and balance,
// Gold correlations against the three-valued theory, the exact Bernoulli-map (AB) codes, the
// filters' band edges, the band-limited waveform against an independent Fourier series, the
// peak factor, and the input checks.
#include "sim/datalink/ab_codes.hpp"
#include "sim/datalink/code_metrics.hpp"
#include "sim/datalink/gold.hpp"
#include "sim/datalink/lfsr.hpp"
#include "sim/datalink/waveform.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <complex>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace dl = rnav::datalink;
using Catch::Matchers::StartsWith;

namespace {

constexpr double kPi = 3.14159265358979323846;

// R in {-1, -t, t-2}, the three values of Gold's theorem.
bool three_valued(long r, long t) { return r == -1 || r == -t || r == t - 2; }

double max_abs_diff(const dl::Signal& a, const dl::Signal& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

// A tone at DFT bin m of a length-L sequence: x_j = e^{2 pi i m j / L}.
dl::Signal tone(std::size_t L, long m) {
  dl::Signal x(L);
  for (std::size_t j = 0; j < L; ++j) x[j] = std::polar(1.0, 2 * kPi * static_cast<double>(m) * static_cast<double>(j) / static_cast<double>(L));
  return x;
}

double max_abs(const dl::Signal& x) {
  double m = 0;
  for (const auto& v : x) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

TEST_CASE("m-sequences: period 2^n - 1, balance 2^(n-1) ones, two-valued autocorrelation", "[datalink][lfsr]") {
  for (int n : {7, 9, 10}) {
    const auto pair = dl::preferred_pair(n);
    for (const auto& taps : {pair.first, pair.second}) {
      INFO("degree " << n);
      const auto s = dl::m_sequence(taps);
      const int N = (1 << n) - 1;
      REQUIRE(static_cast<int>(s.size()) == N);
      CHECK(std::accumulate(s.begin(), s.end(), 0) == (1 << (n - 1)));  // balance
      // R(tau) = -1 for every tau != 0: then no shift 0 < d < N maps the sequence onto itself
      // (that would give R(d) = N), so the least period is N = 2^n - 1, not a divisor of it.
      const auto c = dl::bipolar(s);
      const auto r = dl::periodic_correlation_exact(c, c);
      CHECK(r[0] == N);
      CHECK(std::all_of(r.begin() + 1, r.end(), [](long v) { return v == -1; }));
    }
  }
  // A small case by hand: x^3 + x + 1 from state 111 gives s_{k+3} = s_k + s_{k+1}: 1110010.
  CHECK(dl::m_sequence({3, 1, 0}) == std::vector<int>{1, 1, 1, 0, 0, 1, 0});
}

TEST_CASE("Gold codes, length 127: every pair and every shift in {-1, -t(n), t(n)-2}", "[datalink][gold]") {
  const auto g = dl::GoldFamily::preferred(7);
  REQUIRE(g.length() == 127);
  REQUIRE(g.size() == 129);
  REQUIRE(g.t() == 17);
  std::vector<std::vector<int>> c;
  for (int i = 0; i < g.size(); ++i) c.push_back(g.chips(i));
  long bad = 0, pairs = 0, at_minus_t = 0, at_t_minus_2 = 0;
  for (int i = 0; i < g.size(); ++i) {
    const auto a = dl::periodic_correlation_exact(c[i], c[i]);
    CHECK(a[0] == 127);
    for (std::size_t tau = 1; tau < a.size(); ++tau) bad += !three_valued(a[tau], 17);
    for (int j = i + 1; j < g.size(); ++j) {
      ++pairs;
      for (long r : dl::periodic_correlation_exact(c[i], c[j])) {
        bad += !three_valued(r, 17);
        at_minus_t += r == -17;
        at_t_minus_2 += r == 15;
      }
    }
  }
  CHECK(pairs == 129 * 128 / 2);
  CHECK(bad == 0);
  // The set is not trivially met: both extreme values occur (a family of shifts of one
  // m-sequence would give only -1 and 127).
  CHECK(at_minus_t > 0);
  CHECK(at_t_minus_2 > 0);
  // The members are distinct codes.
  for (int i = 1; i < g.size(); ++i) CHECK(g.bits(i) != g.bits(0));
}

TEST_CASE("Gold codes, lengths 511 and 1023: spot checks against t(9) = 33 and t(10) = 65", "[datalink][gold]") {
  CHECK(dl::GoldFamily::t_of_degree(9) == 33);
  CHECK(dl::GoldFamily::t_of_degree(10) == 65);
  for (int n : {9, 10}) {
    const auto g = dl::GoldFamily::preferred(n);
    const int N = g.length(), t = g.t();
    REQUIRE(N == (1 << n) - 1);
    const std::vector<std::pair<int, int>> pairs = {{0, 1}, {0, 5}, {2, 3}, {100, 400}, {N + 1, 7}, {N / 2, N / 2 + 1}};
    for (const auto& [i, j] : pairs) {
      INFO("degree " << n << ", codes " << i << " and " << j);
      const auto r = dl::periodic_correlation_exact(g.chips(i), g.chips(j));
      CHECK(std::all_of(r.begin(), r.end(), [t](long v) { return three_valued(v, t); }));
      CHECK(*std::min_element(r.begin(), r.end()) == -t);  // the bound is attained
    }
    const auto a = dl::periodic_correlation_exact(g.chips(300), g.chips(300));
    CHECK(std::all_of(a.begin() + 1, a.end(), [t](long v) { return three_valued(v, t); }));
  }
}

TEST_CASE("Correlation through the FFT equals the exact integer correlation", "[datalink][metrics]") {
  const auto g = dl::GoldFamily::preferred(10);
  const auto a = g.chips(3), b = g.chips(700);
  const auto exact = dl::periodic_correlation_exact(a, b);
  const auto fast = dl::periodic_correlation(dl::to_signal(a), dl::to_signal(b));
  // FFT round-off: ~ eps log2(N) sum|a||b| ~ 1e-16 * 10 * 1023 ~ 1e-12; 1e-8 leaves margin and
  // is still far below the integer spacing 1 (and the imaginary part must vanish as well).
  for (std::size_t tau = 0; tau < exact.size(); ++tau) CHECK(std::abs(fast[tau] - static_cast<double>(exact[tau])) < 1e-8);
  const dl::CorrelationBank bank({dl::to_signal(g.chips(0)), dl::to_signal(g.chips(1)), dl::to_signal(a)});
  CHECK(bank.max_offpeak_auto(0) == Approx(1.0).margin(1e-8));  // an m-sequence: |R(tau != 0)| = 1
  CHECK(bank.max_cross(0, 1) == Approx(65.0).margin(1e-8));     // preferred pair: t(10)
}

TEST_CASE("Peak factor: an unfiltered rectangular BPSK code has peak factor 1", "[datalink][waveform]") {
  const auto g = dl::GoldFamily::preferred(7);
  for (int S : {1, 4, 16}) {
    INFO("S = " << S);
    const auto w = dl::bpsk_waveform(dl::to_signal(g.chips(5)), S, dl::Filter::none());
    REQUIRE(w.size() == static_cast<std::size_t>(127 * S));
    CHECK(std::abs(dl::peak_factor(w) - 1.0) < 1e-12);  // |s_j| = 1 for every sample
    const auto ab = dl::ab_code(dl::AbSpec::parse("ab2"), dl::SeedDigits::generic(3, 2), 511);
    CHECK(std::abs(dl::peak_factor(dl::bpsk_waveform(ab, S, dl::Filter::none())) - 1.0) < 1e-12);
    const auto ph = dl::ab_code(dl::AbSpec::parse("ab2-phase"), dl::SeedDigits::generic(3, 2), 511);
    CHECK(std::abs(dl::peak_factor(dl::bpsk_waveform(ph, S, dl::Filter::none())) - 1.0) < 1e-12);
  }
  // A signal with a known peak factor: one period of a sine, peak 1, rms 1/sqrt(2).
  dl::Signal sine(64);
  for (std::size_t j = 0; j < sine.size(); ++j) sine[j] = std::sin(2 * kPi * static_cast<double>(j) / 64.0);
  CHECK(dl::peak_factor(sine) == Approx(std::sqrt(2.0)).epsilon(1e-12));
}

TEST_CASE("Brick-wall filter: a tone at the band edge passes with unit gain, the next one is removed", "[datalink][waveform]") {
  // L = 512 samples at S = 8 per chip: bin m is at f = m S / L = m / 64 chip rates, so B = 1
  // lies on bin 64. Tolerances: FFT round-off ~ eps log2(L) ~ 2e-15 per unit amplitude.
  const std::size_t L = 512;
  const int S = 8;
  const auto f = dl::Filter::brick_wall(1.0);
  for (long m : {64L, -64L, 10L, 0L}) {
    const auto x = tone(L, m);
    CHECK(max_abs_diff(dl::apply_filter(x, S, f), x) < 1e-12);
  }
  for (long m : {65L, -65L, 200L, 256L}) CHECK(max_abs(dl::apply_filter(tone(L, m), S, f)) < 1e-12);
  CHECK(f.response(1.0) == 1.0);
  CHECK(f.response(std::nextafter(1.0, 2.0)) == 0.0);
  CHECK(f.band_edge() == 1.0);
}

TEST_CASE("Raised cosine: H = 1 at (1-beta)/(2T), 1/2 at 1/(2T), 0 at (1+beta)/(2T)", "[datalink][waveform]") {
  for (double beta : {0.25, 0.35, 0.5, 1.0}) {
    INFO("beta " << beta);
    const auto rc = dl::Filter::raised_cosine(0.5, beta);  // B = 1/(2T): the Nyquist raised cosine
    CHECK(rc.response((1 - beta) * 0.5) == Approx(1.0).margin(1e-15));
    CHECK(rc.response(0.5) == Approx(0.5).margin(1e-15));
    CHECK(rc.response(-0.5) == Approx(0.5).margin(1e-15));
    CHECK(rc.response((1 + beta) * 0.5) == Approx(0.0).margin(1e-15));
    CHECK(rc.response(0.5 * (1 + beta) + 1e-9) == 0.0);
    CHECK(rc.band_edge() == Approx(0.5 * (1 + beta)));
    // Non-increasing in |f| across the roll-off.
    double prev = 2;
    for (int k = 0; k <= 100; ++k) {
      const double h = rc.response(0.5 * (1 - beta) + k * beta / 100.0);
      CHECK(h <= prev);
      prev = h;
    }
  }
  // The same through apply_filter: tones on bins 16, 32, 48 of L = 512 at S = 8 are at f = 0.25,
  // 0.5, 0.75 chip rates = (1-beta)/(2T), 1/(2T), (1+beta)/(2T) for beta = 0.5.
  const auto rc = dl::Filter::raised_cosine(0.5, 0.5);
  const std::size_t L = 512;
  CHECK(max_abs(dl::apply_filter(tone(L, 16), 8, rc)) == Approx(1.0).margin(1e-12));
  CHECK(max_abs(dl::apply_filter(tone(L, 32), 8, rc)) == Approx(0.5).margin(1e-12));
  CHECK(max_abs(dl::apply_filter(tone(L, 48), 8, rc)) < 1e-12);
}

TEST_CASE("Band-limited waveform equals an independently summed Fourier series of the NRZ signal", "[datalink][waveform]") {
  // Independent reference: the Fourier coefficient of harmonic m (period N T) of the NRZ waveform,
  // integrated chip by chip,
  //   a_m = sum_k c_k (e^{-2 pi i m k/N} - e^{-2 pi i m (k+1)/N}) / (2 pi i m),  a_0 = mean(c),
  // and y(t_j) = sum_{|m| <= N f_edge} H(m/N) a_m e^{2 pi i m t_j / (N T)}, summed directly (no FFT,
  // no sinc). Round-off of ~2 N f_edge terms of size <= 1: ~1e-13; tolerance 1e-10.
  const auto c = dl::to_signal(dl::bipolar(dl::m_sequence({5, 2, 0})));  // N = 31
  const auto ph = dl::ab_code(dl::AbSpec::parse("ab2-phase"), dl::SeedDigits::generic(9, 2), 31);
  const int S = 8;
  for (const auto& code : {c, ph}) {
    const long N = static_cast<long>(code.size());
    for (const auto& filter : {dl::Filter::brick_wall(2.0), dl::Filter::raised_cosine(0.5, 0.35), dl::Filter::brick_wall(0.5)}) {
      INFO(filter.name());
      const auto y = dl::bpsk_waveform(code, S, filter);
      REQUIRE(y.size() == static_cast<std::size_t>(N * S));
      const long K = static_cast<long>(std::ceil(filter.band_edge() * N));
      std::vector<std::complex<double>> a(static_cast<std::size_t>(2 * K + 1));
      for (long m = -K; m <= K; ++m) {
        std::complex<double> sum = 0;
        for (long k = 0; k < N; ++k) {
          if (m == 0) {
            sum += code[static_cast<std::size_t>(k)] / static_cast<double>(N);
          } else {
            const auto e0 = std::polar(1.0, -2 * kPi * m * k / static_cast<double>(N));
            const auto e1 = std::polar(1.0, -2 * kPi * m * (k + 1) / static_cast<double>(N));
            sum += code[static_cast<std::size_t>(k)] * (e0 - e1) / std::complex<double>(0, 2 * kPi * m);
          }
        }
        a[static_cast<std::size_t>(m + K)] = sum * filter.response(static_cast<double>(m) / N);
      }
      double worst = 0;
      for (long j = 0; j < N * S; j += 5) {
        std::complex<double> v = 0;
        for (long m = -K; m <= K; ++m) v += a[static_cast<std::size_t>(m + K)] * std::polar(1.0, 2 * kPi * m * j / static_cast<double>(N * S));
        worst = std::max(worst, std::abs(v - y[static_cast<std::size_t>(j)]));
      }
      CHECK(worst < 1e-10);
    }
  }
}

TEST_CASE("Power spectrum: Parseval, and a filtered code has no power beyond the band edge", "[datalink][metrics]") {
  const auto g = dl::GoldFamily::preferred(7);
  const auto w = dl::bpsk_waveform(dl::to_signal(g.chips(9)), 8, dl::Filter::brick_wall(1.0));
  const auto p = dl::power_spectrum(w);
  double mean_power = 0;
  for (const auto& v : w) mean_power += std::norm(v) / static_cast<double>(w.size());
  CHECK(std::accumulate(p.begin(), p.end(), 0.0) == Approx(mean_power).epsilon(1e-12));
  // Harmonic q is at q / N chip rates: beyond N * B = 127 (and below L - 127) nothing is left.
  double beyond = 0;
  for (std::size_t q = 128; q < p.size() - 127; ++q) beyond += p[q];
  CHECK(beyond < 1e-24 * mean_power);  // round-off power ~ (1e-15)^2
}

TEST_CASE("AB codes: the doubling map is exact (known seeds give known chips, no collapse after 53 steps)", "[datalink][ab]") {
  // x_0 = 1/7 = 0.001001..._2: the orbit 1/7, 2/7, 4/7, 1/7, ... never ends; chip
  // sgn cos(2 pi x): 1/7 < 1/4 -> +1, 2/7 and 4/7 in [1/4, 3/4] -> -1.
  const auto ab2 = dl::AbSpec::parse("ab2");
  const auto c = dl::ab_code(ab2, dl::SeedDigits::rational(1, 7, 2), 300);
  const double pattern[3] = {1, -1, -1};
  for (std::size_t k = 0; k < c.size(); ++k) {
    INFO("chip " << k);
    CHECK(c[k] == std::complex<double>(pattern[k % 3], 0));
  }
  // The naive double-precision iteration loses a bit per step and collapses to 0 (chip +1 for
  // ever): the failure this generator avoids.
  double x = 1.0 / 7;
  for (int k = 0; k < 60; ++k) x = std::fmod(2 * x, 1.0);
  CHECK(x == 0.0);
  // x_k's value, exact digits rounded once.
  dl::AbOrbit orbit(dl::AbMap::r_adic, dl::SeedDigits::rational(1, 7, 2));
  for (std::size_t k = 0; k < 300; k += 7) CHECK(std::abs(orbit.value(k) - std::ldexp(1.0, static_cast<int>(k % 3)) / 7) < 1e-15);
  // Phase readout: c_k = exp(2 pi i 2^k / 7).
  const auto ph = dl::ab_code(dl::AbSpec::parse("ab2-phase"), dl::SeedDigits::rational(1, 7, 2), 200);
  for (std::size_t k = 0; k < ph.size(); ++k) CHECK(std::abs(ph[k] - std::polar(1.0, 2 * kPi * (1 << (k % 3)) / 7.0)) < 1e-14);
}

TEST_CASE("AB codes: the tent and tripling maps on known orbits, and the exact tie rule", "[datalink][ab]") {
  // Tent map from 1/7: 1/7 -> 2/7 -> 4/7 -> 6/7 -> 2/7 -> ...: chips +1, then (-1, -1, +1) repeated.
  const auto tent = dl::ab_code(dl::AbSpec::parse("tent"), dl::SeedDigits::rational(1, 7, 2), 300);
  CHECK(tent[0] == 1.0);
  const double cycle[3] = {-1, -1, 1};
  for (std::size_t k = 1; k < tent.size(); ++k) CHECK(tent[k].real() == cycle[(k - 1) % 3]);
  // x -> 3x mod 1 from 1/8: 1/8 -> 3/8 -> 1/8 -> ...: chips +1, -1 alternating.
  const auto ab3 = dl::ab_code(dl::AbSpec::parse("ab3"), dl::SeedDigits::rational(1, 8, 3), 300);
  for (std::size_t k = 0; k < ab3.size(); ++k) CHECK(ab3[k].real() == (k % 2 ? -1.0 : 1.0));
  // From 1/4 (= 0.0202..._3) the orbit is 1/4, 3/4, 1/4, ...: exactly on the boundary, where
  // cos(2 pi x) = 0 and the chip is -1 by definition. The comparison must find equality exactly.
  dl::AbOrbit o(dl::AbMap::r_adic, dl::SeedDigits::rational(1, 4, 3));
  CHECK(o.compare(0, 1, 4) == 0);
  CHECK(o.compare(1, 3, 4) == 0);
  CHECK(o.compare(0, 3, 4) < 0);
  const auto tie = dl::ab_code(dl::AbSpec::parse("ab3"), dl::SeedDigits::rational(1, 4, 3), 4);
  for (const auto& v : tie) CHECK(v.real() == -1.0);
}

TEST_CASE("AB codes: generic seeds give balanced, non-collapsing, reproducible codes", "[datalink][ab]") {
  // ab2 chip k = (-1)^(d_{k+1} XOR d_{k+2}): with i.i.d. fair digits the chips are i.i.d. fair.
  // N = 1023: the number of +1 is N/2 +- 16 (1 sigma); bounds at 8 sigma. Sign changes after
  // chip 53 (where a double-precision orbit would be constant): ~485 +- 16; bound at > 300.
  const int N = 1023;
  for (const char* name : {"ab2", "ab3", "tent"}) {
    INFO(name);
    const auto spec = dl::AbSpec::parse(name);
    const auto c = dl::ab_code(spec, dl::SeedDigits::generic(42, spec.base), N);
    long plus = 0, changes = 0;
    for (int k = 0; k < N; ++k) plus += c[static_cast<std::size_t>(k)].real() > 0;
    for (int k = 54; k < N; ++k) changes += c[static_cast<std::size_t>(k)] != c[static_cast<std::size_t>(k - 1)];
    CHECK(std::abs(plus - N / 2.0) < 8 * 16);
    CHECK(changes > 300);
    CHECK(dl::ab_code(spec, dl::SeedDigits::generic(42, spec.base), N) == c);  // reproducible
    CHECK(dl::ab_code(spec, dl::SeedDigits::generic(43, spec.base), N) != c);  // the seed indexes the family
  }
  // The tent map's binary code is the doubling map's (T(x) = +-2x mod 1, cos even); the phase
  // readout differs (exp(2 pi i x) is not even).
  for (std::uint64_t seed : {1u, 2u, 77u}) {
    CHECK(dl::ab_code(dl::AbSpec::parse("tent"), dl::SeedDigits::generic(seed, 2), N) ==
          dl::ab_code(dl::AbSpec::parse("ab2"), dl::SeedDigits::generic(seed, 2), N));
    CHECK(dl::ab_code(dl::AbSpec::parse("tent-phase"), dl::SeedDigits::generic(seed, 2), 64) !=
          dl::ab_code(dl::AbSpec::parse("ab2-phase"), dl::SeedDigits::generic(seed, 2), 64));
  }
  // ab3 chips are correlated, E[c_k c_{k+j}] = (-1/3)^j (ab_codes.hpp); ab2's are not. Sample
  // means over 20 codes of 1023 chips (20440 products, sd <= 1/sqrt(20440) = 0.007): bound 0.05.
  for (const char* name : {"ab3", "ab2"}) {
    const auto spec = dl::AbSpec::parse(name);
    double lag1 = 0, lag2 = 0;
    long n = 0;
    for (std::uint64_t seed = 100; seed < 120; ++seed) {
      const auto c = dl::ab_code(spec, dl::SeedDigits::generic(seed, spec.base), N);
      for (int k = 0; k + 2 < N; ++k, ++n) {
        lag1 += (c[static_cast<std::size_t>(k)] * c[static_cast<std::size_t>(k + 1)]).real();
        lag2 += (c[static_cast<std::size_t>(k)] * c[static_cast<std::size_t>(k + 2)]).real();
      }
    }
    INFO(name);
    CHECK(std::abs(lag1 / n - (spec.base == 3 ? -1.0 / 3 : 0.0)) < 0.05);
    CHECK(std::abs(lag2 / n - (spec.base == 3 ? 1.0 / 9 : 0.0)) < 0.05);
  }
  // The readout of ab2 against the seed's digits.
  auto digits = dl::SeedDigits::generic(5, 2);
  const auto c = dl::ab_code(dl::AbSpec::parse("ab2"), dl::SeedDigits::generic(5, 2), 200);
  for (std::size_t k = 0; k < c.size(); ++k)
    CHECK(c[k].real() == ((digits.digit(k + 1) ^ digits.digit(k + 2)) ? -1.0 : 1.0));
}

TEST_CASE("Bad parameters throw std::invalid_argument naming the parameter", "[datalink][errors]") {
  CHECK_THROWS_WITH(dl::Filter::brick_wall(0.0), StartsWith("bandwidth"));
  CHECK_THROWS_WITH(dl::Filter::brick_wall(std::nan("")), StartsWith("bandwidth"));
  CHECK_THROWS_WITH(dl::Filter::raised_cosine(-1.0, 0.5), StartsWith("bandwidth"));
  CHECK_THROWS_WITH(dl::Filter::raised_cosine(0.5, 0.0), StartsWith("rolloff"));
  CHECK_THROWS_WITH(dl::Filter::raised_cosine(0.5, 1.2), StartsWith("rolloff"));
  CHECK_THROWS_WITH(dl::Filter::parse("brik:1"), StartsWith("filter"));
  CHECK_THROWS_WITH(dl::Filter::parse("rc:0.5:x"), StartsWith("filter"));
  CHECK(dl::Filter::parse("rc:0.5:0.35").name() == "rc:0.5:0.35");
  const auto code = dl::to_signal(dl::bipolar(dl::m_sequence({5, 2, 0})));
  CHECK_THROWS_WITH(dl::bpsk_waveform(code, 0, dl::Filter::none()), StartsWith("samples_per_chip"));
  CHECK_THROWS_WITH(dl::bpsk_waveform(code, 4, dl::Filter::brick_wall(2.0)), StartsWith("samples_per_chip"));
  CHECK_THROWS_WITH(dl::bpsk_waveform({}, 4, dl::Filter::none()), StartsWith("chips"));
  CHECK_THROWS_WITH(dl::apply_filter(code, 0, dl::Filter::brick_wall(1.0)), StartsWith("samples_per_chip"));
  CHECK_THROWS_WITH(dl::m_sequence({4, 2, 0}), StartsWith("taps"));  // (x^2 + x + 1)^2
  CHECK_THROWS_WITH(dl::m_sequence({6, 3, 0}), StartsWith("taps"));  // irreducible, order 9
  CHECK_THROWS_WITH(dl::m_sequence({7, 3}), StartsWith("taps"));     // no constant term
  CHECK_THROWS_WITH(dl::m_sequence({}), StartsWith("taps"));
  CHECK_THROWS_WITH(dl::m_sequence({30, 1, 0}), StartsWith("taps"));
  CHECK_THROWS_WITH(dl::bipolar({0, 2}), StartsWith("bits"));
  CHECK_THROWS_WITH(dl::preferred_pair(8), StartsWith("degree"));
  CHECK_THROWS_WITH(dl::GoldFamily({7, 3, 0}, {7, 3, 0}), StartsWith("preferred pair"));  // u with itself: peak 127
  CHECK_THROWS_WITH(dl::GoldFamily({7, 3, 0}, {9, 4, 0}), StartsWith("taps_v"));
  CHECK_THROWS_WITH(dl::GoldFamily({7, 3, 1}, {7, 3, 0}), StartsWith("taps_u"));
  const auto g = dl::GoldFamily::preferred(7);
  CHECK_THROWS_WITH(g.bits(-1), StartsWith("index"));
  CHECK_THROWS_WITH(g.bits(129), StartsWith("index"));
  CHECK_THROWS_WITH(dl::SeedDigits::rational(1, 4, 2), StartsWith("q"));
  CHECK_THROWS_WITH(dl::SeedDigits::rational(7, 7, 2), StartsWith("p"));
  CHECK_THROWS_WITH(dl::SeedDigits::generic(1, 1), StartsWith("base"));
  CHECK_THROWS_WITH(dl::ab_code(dl::AbSpec::parse("ab2"), dl::SeedDigits::generic(1, 2), 0), StartsWith("length"));
  CHECK_THROWS_WITH(dl::ab_code(dl::AbSpec::parse("ab3"), dl::SeedDigits::generic(1, 2), 10), StartsWith("seed"));
  CHECK_THROWS_WITH(dl::AbSpec::parse("ab1"), StartsWith("family"));
  CHECK_THROWS_WITH(dl::AbSpec::parse("bernoulli"), StartsWith("family"));
  CHECK_THROWS_WITH(dl::AbOrbit(dl::AbMap::tent, dl::SeedDigits::generic(1, 3)), StartsWith("seed"));
  CHECK_THROWS_WITH(dl::peak_factor({}), StartsWith("s"));
  CHECK_THROWS_WITH(dl::peak_factor(dl::Signal(4, 0.0)), StartsWith("s"));
  CHECK_THROWS_WITH(dl::periodic_correlation_exact({1, -1}, {1}), StartsWith("b"));
  CHECK_THROWS_WITH(dl::CorrelationBank({code, dl::Signal(5, 1.0)}), StartsWith("codes"));
}
