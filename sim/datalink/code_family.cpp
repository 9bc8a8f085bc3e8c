#include "sim/datalink/code_family.hpp"

#include "sim/datalink/ab_codes.hpp"
#include "sim/datalink/code_metrics.hpp"
#include "sim/datalink/gold.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav::datalink {

int gold_degree_of_length(int length) {
  switch (length) {
    case 127: return 7;
    case 511: return 9;
    case 1023: return 10;
    default:
      throw std::invalid_argument("length: " + std::to_string(length) +
                                  " chips: Gold codes need 127, 511 or 1023 (the lengths with a stored preferred pair)");
  }
}

bool known_family(const std::string& family) {
  if (family == "gold" || family == "gold-qpsk") return true;
  try {
    AbSpec::parse(family);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

std::vector<FamilyCode> family_codes(const std::string& family, int length, int count, std::uint64_t seed0) {
  std::vector<FamilyCode> codes;
  if (family == "gold" || family == "gold-qpsk") {
    const auto g = GoldFamily::preferred(gold_degree_of_length(length));
    const long size = g.size();
    if (count < 1 || count > size)
      throw std::invalid_argument("count: " + std::to_string(count) + " codes: a Gold family of length " +
                                  std::to_string(length) + " has 1 ... " + std::to_string(size));
    for (int s = 0; s < count; ++s) {
      const long i = static_cast<long>(s) * size / count;
      Signal c = to_signal(g.chips(static_cast<int>(i)));
      if (family == "gold-qpsk") {
        const auto q = g.chips(static_cast<int>((i + size / 2) % size));
        for (std::size_t k = 0; k < c.size(); ++k) c[k] = std::complex<double>(c[k].real(), q[k]) / std::sqrt(2.0);
      }
      codes.push_back({i, std::move(c)});
    }
    return codes;
  }
  if (!known_family(family))
    throw std::invalid_argument("family: '" + family + "' is not gold, gold-qpsk, abR (R = 2..16), tent, or abR/tent with -phase");
  if (count < 1 || count > 1000000) throw std::invalid_argument("count: " + std::to_string(count) + " codes is outside [1, 1e6]");
  const auto spec = AbSpec::parse(family);
  for (int s = 0; s < count; ++s) {
    const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(s);
    codes.push_back({static_cast<long>(seed), ab_code(spec, SeedDigits::generic(seed, spec.base), length)});
  }
  return codes;
}

double family_peak_factor(const std::string& family, int length, const Filter& filter, double q, int count,
                          int samples_per_chip) {
  if (!(q >= 0 && q <= 1)) throw std::invalid_argument("quantile: " + std::to_string(q) + " must lie in [0, 1]");
  std::vector<double> pf;
  for (const auto& c : family_codes(family, length, count, 1))
    pf.push_back(peak_factor(bpsk_waveform(c.chips, samples_per_chip, filter)));
  std::sort(pf.begin(), pf.end());
  // numpy's default quantile: h = (n - 1) q, x[floor h] + (h - floor h) (x[floor h + 1] - x[floor h])
  const double h = static_cast<double>(pf.size() - 1) * q;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, pf.size() - 1);
  return pf[lo] + (h - static_cast<double>(lo)) * (pf[hi] - pf[lo]);
}

}  // namespace rnav::datalink
