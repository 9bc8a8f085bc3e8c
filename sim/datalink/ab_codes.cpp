#include "sim/datalink/ab_codes.hpp"

#include <cmath>
#include <complex>
#include <numeric>
#include <stdexcept>
#include <string>

namespace rnav::datalink {

namespace {

constexpr std::uint64_t kMaxDenominator = std::uint64_t{1} << 20;
// Fine-Wilf: two eventually periodic digit strings (pre-period <= 64, periods <= 2^20 each) that
// agree on this many digits agree on all of them.
constexpr std::size_t kCompareDigits = (std::size_t{1} << 21) + 128;

void check_base(int base) {
  if (base < 2 || base > 16) throw std::invalid_argument("base: " + std::to_string(base) + " outside [2, 16]");
}

// SplitMix64 (Steele, Lea, Flood 2014): state += golden gamma, then the finaliser.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

SeedDigits SeedDigits::rational(std::uint64_t p, std::uint64_t q, int base) {
  check_base(base);
  if (q < 1 || q > kMaxDenominator) throw std::invalid_argument("q: " + std::to_string(q) + " outside [1, 2^20]");
  if (std::gcd(q, static_cast<std::uint64_t>(base)) != 1)
    throw std::invalid_argument("q: " + std::to_string(q) + " shares a factor with the base " + std::to_string(base) +
                                " (a terminating expansion has two digit strings)");
  if (p >= q) throw std::invalid_argument("p: " + std::to_string(p) + " is not below q = " + std::to_string(q) + " (x_0 must be in [0, 1))");
  return SeedDigits(base, true, p, q);
}

SeedDigits SeedDigits::generic(std::uint64_t seed, int base) {
  check_base(base);
  std::uint64_t state = seed;
  const std::uint64_t start = splitmix64(state);  // hash the seed: neighbouring seeds, unrelated streams
  return SeedDigits(base, false, start, 0);
}

void SeedDigits::extend() {
  const auto r = static_cast<std::uint64_t>(base_);
  if (rational_) {
    // d_i = floor(r rem / q), rem <- r rem mod q   (rem < q <= 2^20: no overflow)
    for (int n = 0; n < 64; ++n) {
      const std::uint64_t t = r * a_;
      d_.push_back(static_cast<std::uint8_t>(t / b_));
      a_ = t % b_;
    }
    return;
  }
  if (base_ == 2) {
    const std::uint64_t w = splitmix64(a_);
    for (int bit = 63; bit >= 0; --bit) d_.push_back(static_cast<std::uint8_t>((w >> bit) & 1u));
    return;
  }
  // One uniform digit per accepted word: reject w >= r floor(2^64 / r).
  const std::uint64_t limit = (~std::uint64_t{0} / r) * r;
  for (int n = 0; n < 64; ++n) {
    std::uint64_t w;
    do w = splitmix64(a_);
    while (w >= limit);
    d_.push_back(static_cast<std::uint8_t>(w % r));
  }
}

int SeedDigits::digit(std::size_t i) {
  if (i == 0) throw std::invalid_argument("i: digits are numbered from 1");
  while (d_.size() < i) extend();
  return d_[i - 1];
}

std::string AbSpec::name() const {
  std::string s = map == AbMap::tent ? "tent" : "ab" + std::to_string(base);
  if (readout == AbReadout::phase) s += "-phase";
  return s;
}

AbSpec AbSpec::parse(const std::string& name) {
  AbSpec s;
  std::string core = name;
  const std::string suffix = "-phase";
  if (core.size() > suffix.size() && core.compare(core.size() - suffix.size(), suffix.size(), suffix) == 0) {
    s.readout = AbReadout::phase;
    core.resize(core.size() - suffix.size());
  }
  if (core == "tent") {
    s.map = AbMap::tent;
    s.base = 2;
    return s;
  }
  if (core.size() >= 3 && core.compare(0, 2, "ab") == 0 && core.find_first_not_of("0123456789", 2) == std::string::npos &&
      core.size() <= 4) {
    s.base = std::stoi(core.substr(2));
    if (s.base >= 2 && s.base <= 16) return s;
  }
  throw std::invalid_argument("family: '" + name + "' is not abR (R = 2..16), tent, or either with -phase");
}

AbOrbit::AbOrbit(AbMap map, SeedDigits seed) : map_(map), seed_(std::move(seed)) {
  if (map_ == AbMap::tent && seed_.base() != 2)
    throw std::invalid_argument("seed: the tent map needs base-2 digits, got base " + std::to_string(seed_.base()));
}

int AbOrbit::digit(std::size_t k, std::size_t i) {
  if (i == 0) throw std::invalid_argument("i: digits are numbered from 1");
  const int d = seed_.digit(k + i);
  if (map_ == AbMap::r_adic) return d;  // x_k = sum_i d_{k+i} r^-i
  // tent: e_{k,i} = d_{k+i} XOR d_k, d_0 = 0
  return k == 0 ? d : d ^ seed_.digit(k);
}

int AbOrbit::compare(std::size_t k, std::uint64_t p, std::uint64_t q) {
  if (q < 1 || q > kMaxDenominator) throw std::invalid_argument("q: " + std::to_string(q) + " outside [1, 2^20]");
  if (p >= q) throw std::invalid_argument("p: " + std::to_string(p) + " is not below q = " + std::to_string(q));
  const auto r = static_cast<std::uint64_t>(seed_.base());
  std::uint64_t rem = p;
  // Lexicographic comparison of the digit strings of x_k and p/q (long division for p/q's).
  for (std::size_t i = 1; i <= kCompareDigits; ++i) {
    const std::uint64_t t = r * rem;
    const int dp = static_cast<int>(t / q);
    rem = t % q;
    const int dx = digit(k, i);
    if (dx != dp) return dx < dp ? -1 : 1;
  }
  return 0;
}

double AbOrbit::value(std::size_t k) {
  const int r = seed_.base();
  const auto D = static_cast<std::size_t>(std::ceil(64.0 / std::log2(static_cast<double>(r))));
  // Horner from the last digit: x = (e_1 + (e_2 + ... (e_D) / r ...) / r) / r
  double x = 0;
  for (std::size_t i = D; i >= 1; --i) x = (x + digit(k, i)) / r;
  return x;
}

Signal ab_code(const AbSpec& spec, SeedDigits seed, int length) {
  if (length < 1 || length > (1 << 24)) throw std::invalid_argument("length: " + std::to_string(length) + " outside [1, 2^24]");
  if (seed.base() != spec.base)
    throw std::invalid_argument("seed: base " + std::to_string(seed.base()) + " differs from family " + spec.name() + "'s base " +
                                std::to_string(spec.base));
  AbOrbit orbit(spec.map, std::move(seed));
  Signal c(static_cast<std::size_t>(length));
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (spec.readout == AbReadout::phase) {
      // c_k = exp(2 pi i x_k)
      c[k] = std::polar(1.0, 2 * M_PI * orbit.value(k));
    } else {
      // c_k = sgn cos(2 pi x_k): +1 iff x_k < 1/4 or x_k > 3/4
      c[k] = (orbit.compare(k, 1, 4) < 0 || orbit.compare(k, 3, 4) > 0) ? 1.0 : -1.0;
    }
  }
  return c;
}

}  // namespace rnav::datalink
