// Maximal-length sequences (m-sequences) over GF(2) from a linear feedback shift register, and
// the preferred pairs of primitive polynomials that Gold families (gold.hpp) are built from.
//
// A polynomial is given as the list of its exponents ("tap list"): {10, 3, 0} is
// h(x) = x^10 + x^3 + 1. The register of degree n produces the binary sequence s_0, s_1, ...
// with characteristic polynomial h:
//
//   s_{k+n} = sum_{i=0}^{n-1} h_i s_{k+i}   (mod 2),     s_0 = ... = s_{n-1} = 1,
//
// which, for a primitive h, has period N = 2^n - 1 and holds 2^(n-1) ones and 2^(n-1) - 1
// zeros per period; every non-zero start state gives a cyclic shift of the same sequence.
#pragma once

#include <utility>
#include <vector>

namespace rnav::datalink {

/// The m-sequence of a primitive polynomial: one period, N = 2^n - 1 bits (0/1), from the
/// all-ones start state.
/// @param taps  exponents of h(x), each in [0, n], containing n (the degree, 2 <= n <= 24) and 0,
///              no exponent twice; h must be primitive (checked: the register must run through
///              all 2^n - 1 non-zero states before it repeats). Throws std::invalid_argument
///              naming "taps" otherwise.
std::vector<int> m_sequence(const std::vector<int>& taps);

/// Bits to bipolar chips: c = (-1)^b, i.e. 0 -> +1, 1 -> -1 (so XOR of bits is the product of
/// chips). Throws std::invalid_argument naming "bits" for a value other than 0 or 1.
std::vector<int> bipolar(const std::vector<int>& bits);

/// A preferred pair of primitive polynomials (tap lists) of degree n in {7, 9, 10}; throws
/// std::invalid_argument naming "degree" for any other n (n = 8 and every multiple of 4 has no
/// preferred pair). Sources, quoted from memory and therefore not trusted: each pair is checked
/// to be preferred (its cross-correlation takes only the three values of gold.hpp) whenever a
/// GoldFamily is built, and in test/test_datalink_codes.cpp:
///   n = 7:  x^7 + x^3 + 1 and x^7 + x^3 + x^2 + x + 1, and
///   n = 9:  x^9 + x^4 + 1 and x^9 + x^6 + x^4 + x^3 + 1: the preferred-pair table of the
///           MATLAB Communications Toolbox documentation (comm.GoldSequence), after R. C. Dixon,
///           "Spread Spectrum Systems with Commercial Applications";
///   n = 10: x^10 + x^3 + 1 and x^10 + x^9 + x^8 + x^6 + x^3 + x^2 + 1, the GPS C/A code's G1 and
///           G2 registers (IS-GPS-200, section 3.3.2.3).
std::pair<std::vector<int>, std::vector<int>> preferred_pair(int degree);

}  // namespace rnav::datalink
