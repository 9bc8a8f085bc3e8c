#include "sim/datalink/lfsr.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace rnav::datalink {

namespace {

std::string poly_text(const std::vector<int>& taps) {
  std::vector<int> t = taps;
  std::sort(t.rbegin(), t.rend());
  std::string s;
  for (int e : t) s += (s.empty() ? "" : " + ") + (e == 0 ? std::string("1") : e == 1 ? std::string("x") : "x^" + std::to_string(e));
  return s;
}

}  // namespace

std::vector<int> m_sequence(const std::vector<int>& taps) {
  if (taps.empty()) throw std::invalid_argument("taps: empty tap list (expected the exponents of h(x), e.g. {10, 3, 0})");
  const int n = *std::max_element(taps.begin(), taps.end());
  if (n < 2 || n > 24) throw std::invalid_argument("taps: degree " + std::to_string(n) + " outside [2, 24]");
  std::vector<int> h(static_cast<std::size_t>(n) + 1, 0);
  for (int e : taps) {
    if (e < 0) throw std::invalid_argument("taps: negative exponent " + std::to_string(e));
    if (h[static_cast<std::size_t>(e)]) throw std::invalid_argument("taps: exponent " + std::to_string(e) + " given twice");
    h[static_cast<std::size_t>(e)] = 1;
  }
  if (!h[0]) throw std::invalid_argument("taps: " + poly_text(taps) + " has no constant term (not primitive)");
  // The register holds (s_k, ..., s_{k+n-1}) as bits 0..n-1 of `state`;
  //   s_{k+n} = sum_{i<n} h_i s_{k+i} (mod 2) = parity(state & mask), mask bit i = h_i.
  std::uint32_t mask = 0;
  for (int i = 0; i < n; ++i)
    if (h[static_cast<std::size_t>(i)]) mask |= 1u << i;
  const std::uint32_t start = (1u << n) - 1u;  // all ones
  const std::uint32_t period = (1u << n) - 1u;
  std::vector<int> s(period);
  std::uint32_t state = start;
  for (std::uint32_t k = 0; k < period; ++k) {
    s[k] = static_cast<int>(state & 1u);
    const std::uint32_t next = static_cast<std::uint32_t>(__builtin_parity(state & mask));
    state = (state >> 1) | (next << (n - 1));
    // Primitive <=> the state first returns to the start after exactly 2^n - 1 steps.
    if (state == start && k + 1 < period)
      throw std::invalid_argument("taps: " + poly_text(taps) + " is not primitive (period " + std::to_string(k + 1) +
                                  " < 2^" + std::to_string(n) + " - 1)");
  }
  if (state != start)
    throw std::invalid_argument("taps: " + poly_text(taps) + " is not primitive (the register does not return to its start state)");
  return s;
}

std::vector<int> bipolar(const std::vector<int>& bits) {
  std::vector<int> c(bits.size());
  for (std::size_t i = 0; i < bits.size(); ++i) {
    if (bits[i] != 0 && bits[i] != 1) throw std::invalid_argument("bits: value " + std::to_string(bits[i]) + " at " + std::to_string(i) + " is not 0 or 1");
    c[i] = 1 - 2 * bits[i];  // (-1)^b
  }
  return c;
}

std::pair<std::vector<int>, std::vector<int>> preferred_pair(int degree) {
  switch (degree) {
    case 7: return {{7, 3, 0}, {7, 3, 2, 1, 0}};
    case 9: return {{9, 4, 0}, {9, 6, 4, 3, 0}};
    case 10: return {{10, 3, 0}, {10, 9, 8, 6, 3, 2, 0}};
    default:
      throw std::invalid_argument("degree: no preferred pair stored for degree " + std::to_string(degree) + " (stored: 7, 9, 10)");
  }
}

}  // namespace rnav::datalink
