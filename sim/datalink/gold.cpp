#include "sim/datalink/gold.hpp"

#include "sim/datalink/code_metrics.hpp"
#include "sim/datalink/lfsr.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rnav::datalink {

namespace {

std::vector<int> checked_sequence(const std::vector<int>& taps, const char* name) {
  try {
    return m_sequence(taps);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(name) + ": " + e.what());
  }
}

}  // namespace

int GoldFamily::t_of_degree(int n) {
  if (n < 2 || n % 4 == 0) throw std::invalid_argument("degree: no preferred pairs (and no t(n)) for n = " + std::to_string(n));
  // t(n) = 2^((n+1)/2) + 1 for odd n, 2^((n+2)/2) + 1 for n = 2 mod 4.
  return n % 2 ? (1 << ((n + 1) / 2)) + 1 : (1 << ((n + 2) / 2)) + 1;
}

GoldFamily::GoldFamily(const std::vector<int>& taps_u, const std::vector<int>& taps_v)
    : u_(checked_sequence(taps_u, "taps_u")), v_(checked_sequence(taps_v, "taps_v")) {
  if (u_.size() != v_.size())
    throw std::invalid_argument("taps_v: degree differs from taps_u's (" + std::to_string(v_.size()) + " vs " +
                                std::to_string(u_.size()) + " chips)");
  n_ = *std::max_element(taps_u.begin(), taps_u.end());
  if (n_ % 4 == 0) throw std::invalid_argument("preferred pair: none exists for a degree that is a multiple of 4 (n = " + std::to_string(n_) + ")");
  const long t = t_of_degree(n_);
  const auto r = periodic_correlation_exact(bipolar(u_), bipolar(v_));
  for (std::size_t tau = 0; tau < r.size(); ++tau)
    if (r[tau] != -1 && r[tau] != -t && r[tau] != t - 2)
      throw std::invalid_argument("preferred pair: cross-correlation " + std::to_string(r[tau]) + " at shift " + std::to_string(tau) +
                                  " is not in {-1, " + std::to_string(-t) + ", " + std::to_string(t - 2) + "}");
}

GoldFamily GoldFamily::preferred(int degree) {
  const auto p = preferred_pair(degree);
  return GoldFamily(p.first, p.second);
}

std::vector<int> GoldFamily::bits(int index) const {
  const int N = length();
  if (index < 0 || index >= N + 2)
    throw std::invalid_argument("index: " + std::to_string(index) + " outside [0, " + std::to_string(N + 2) + ")");
  if (index == 0) return u_;
  if (index == 1) return v_;
  const int k = index - 2;
  // u XOR T^k v: b_i = u_i XOR v_{(i+k) mod N}.
  std::vector<int> b(static_cast<std::size_t>(N));
  for (int i = 0; i < N; ++i) b[static_cast<std::size_t>(i)] = u_[static_cast<std::size_t>(i)] ^ v_[static_cast<std::size_t>((i + k) % N)];
  return b;
}

std::vector<int> GoldFamily::chips(int index) const { return bipolar(bits(index)); }

}  // namespace rnav::datalink
