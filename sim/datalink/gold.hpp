// Gold codes (R. Gold, "Optimal binary sequences for spread spectrum multiplexing", IEEE Trans.
// Inf. Theory 13 (1967) 619-621): from a preferred pair u, v of m-sequences of period
// N = 2^n - 1 (lfsr.hpp), the family of N + 2 sequences
//
//   G(u, v) = { u, v, u XOR T^k v : k = 0, ..., N-1 },    (T^k v)_i = v_{(i+k) mod N}.
//
// As chips c = (-1)^b (XOR becomes the product), the periodic correlation of any two members a, b
//   R_ab(tau) = sum_{i=0}^{N-1} a_i b_{(i+tau) mod N}
// takes, for every tau (and for a = b at every tau != 0), only the three values
//   { -1, -t(n), t(n) - 2 },   t(n) = 2^((n+1)/2) + 1 (n odd),  2^((n+2)/2) + 1 (n = 2 mod 4),
// which for a preferred pair is the definition this class checks when it is built.
#pragma once

#include <vector>

namespace rnav::datalink {

class GoldFamily {
 public:
  /// @param taps_u, taps_v  primitive polynomials of the same degree n (tap lists as in
  ///                        m_sequence, 2 <= n <= 24, n not a multiple of 4) forming a preferred
  ///                        pair. Throws std::invalid_argument naming "taps_u"/"taps_v" (not
  ///                        primitive, degrees differ) or "preferred pair" (a cross-correlation
  ///                        value outside the three-valued set).
  GoldFamily(const std::vector<int>& taps_u, const std::vector<int>& taps_v);
  /// The family of the stored preferred pair of degree n in {7, 9, 10} (lfsr.hpp).
  static GoldFamily preferred(int degree);

  int degree() const { return n_; }
  /// N = 2^n - 1 [chips]
  int length() const { return static_cast<int>(u_.size()); }
  /// N + 2 codes
  int size() const { return length() + 2; }
  /// t(n) above.
  int t() const { return t_of_degree(n_); }
  static int t_of_degree(int n);

  /// Code `index` as bits 0/1: index 0 is u, 1 is v, 2 + k is u XOR T^k v (k = 0..N-1).
  /// Throws std::invalid_argument naming "index" outside [0, N + 2).
  std::vector<int> bits(int index) const;
  /// The same code as chips (-1)^b in {+1, -1}.
  std::vector<int> chips(int index) const;

 private:
  int n_ = 0;
  std::vector<int> u_, v_;
};

}  // namespace rnav::datalink
