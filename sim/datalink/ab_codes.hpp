// Nonlinear noise-like codes from the Bernoulli (doubling) map and its relatives: our reading of
// the "AB codes" of L. Auslander and P. E. Barbano, "Communication codes and Bernoulli
// transformations", Appl. Comput. Harmon. Anal. 5 (1998) 109-128 (the paper itself was not at
// hand; the reading is stated here and in the README so that it can be checked against it).
//
// The map. A point x_0 in [0, 1) and the orbit x_{k+1} = F(x_k) of one of
//   r-adic map (r = 2: the Bernoulli / doubling map)   F(x) = r x mod 1,
//   tent map                                            F(x) = 1 - |1 - 2 x|   (= 2x, or 2 - 2x),
// The Bernoulli map is the shift of the base-r digits: with x_0 = sum_{i>=1} d_i r^-i,
//   x_k = sum_{i>=1} d_{k+i} r^-i,
// and the tent map is the shift with a complement: the binary digits of x_k are
//   e_{k,i} = d_{k+i} XOR d_k     (d_0 = 0),
// because 2 - 2x = 1 - (2x - 1) complements every digit after the leading 1.
//
// Exactness. In double precision, x -> 2x mod 1 loses one bit of x per step, and every orbit
// collapses to 0 after ~53 steps. Here the state is the digit string itself (SeedDigits, as long
// as needed, produced on demand), so x_k is exact for every k: the code never collapses.
//
// The code. Chip k of a code of length N is a readout of x_k, k = 0 .. N-1 (the first N points
// of the orbit, starting at x_0); the N chips are then used periodically, as every code here is:
//   sign_cos (binary, BPSK):  c_k = sgn cos(2 pi x_k) = +1 if x_k < 1/4 or x_k > 3/4,
//                                                        -1 if 1/4 <= x_k <= 3/4
//                             (the comparison with 1/4 and 3/4 is exact, digit by digit);
//   phase (polyphase, unimodular):  c_k = exp(2 pi i x_k), x_k rounded to a double at readout.
// For the doubling map with sign_cos, c_k = +1 exactly when the first two digits of x_k agree:
//   c_k = (-1)^(d_{k+1} XOR d_{k+2}).
// The tent map gives the same binary code: T(x) = 2x or 2 - 2x = -2x (mod 1), so tent orbits are
// +-2^k x_0 (mod 1), and cos(2 pi (-y)) = cos(2 pi y); only the phase readout tells them apart.
// For a Lebesgue-typical x_0 the digits are independent fair coins, so ab2 (and tent) codes are
// i.i.d. fair +-1 chips. x -> 3x mod 1 with sign_cos gives correlated chips: with the Fourier
// series sgn cos(2 pi x) = sum_{m odd} (2 / (pi |m|)) (-1)^((|m|-1)/2) e^{2 pi i m x}, only the
// harmonics m and 3^j m of c_k and c_{k+j} meet, and E[c_k c_{k+j}] = (-1/3)^j.
//
// The family. A code family is indexed by the seed point x_0: SeedDigits::generic(j, r) gives
// code j the digits of a pseudo-random point (SplitMix64 stream of j), a stand-in for a
// Lebesgue-typical ("normal") x_0; SeedDigits::rational(p, q, r) gives the exact x_0 = p/q
// (for tests and known orbits).
#pragma once

#include "sim/datalink/signal.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rnav::datalink {

/// The base-r digits d_1, d_2, ... of a seed point x_0 = sum d_i r^-i in [0, 1), produced on
/// demand and kept.
class SeedDigits {
 public:
  /// x_0 = p/q exactly (long division: rem_0 = p, d_i = floor(r rem_{i-1} / q),
  /// rem_i = r rem_{i-1} mod q).
  /// @param p     numerator, 0 <= p < q
  /// @param q     denominator, 1 <= q <= 2^20, coprime to r (so that the expansion does not
  ///              terminate and is unique); throws std::invalid_argument naming "q" or "p"
  /// @param base  r in [2, 16] (throws naming "base")
  static SeedDigits rational(std::uint64_t p, std::uint64_t q, int base);
  /// A generic point: d_i uniform and independent from the SplitMix64 stream of `seed` (any
  /// value; base 2 takes 64 digits per 64-bit word, most significant first; other bases one
  /// digit per word, by rejection of the top 2^64 mod r values).
  /// @param base  r in [2, 16] (throws naming "base")
  static SeedDigits generic(std::uint64_t seed, int base);

  int base() const { return base_; }
  /// d_i, i >= 1 (throws std::invalid_argument naming "i" for i = 0).
  int digit(std::size_t i);

 private:
  SeedDigits(int base, bool rational, std::uint64_t a, std::uint64_t b) : base_(base), rational_(rational), a_(a), b_(b) {}
  void extend();
  int base_;
  bool rational_;
  std::uint64_t a_, b_;  // rational: remainder, q; generic: SplitMix64 state, unused
  std::vector<std::uint8_t> d_;  // d_[i-1] = d_i
};

enum class AbMap { r_adic, tent };
enum class AbReadout { sign_cos, phase };

/// A code family: the map, its base r, the readout.
struct AbSpec {
  AbMap map = AbMap::r_adic;
  int base = 2;  ///< r in [2, 16]; the tent map needs 2
  AbReadout readout = AbReadout::sign_cos;
  /// "abR" (r-adic, R = r), "tent"; "-phase" appended for the phase readout: "ab2", "ab3",
  /// "tent", "ab2-phase".
  std::string name() const;
  /// Inverse of name(); throws std::invalid_argument naming "family".
  static AbSpec parse(const std::string& name);
};

/// The orbit x_k = F^k(x_0), exact, as digit strings.
class AbOrbit {
 public:
  /// @param map   the map (the tent map needs seed.base() == 2: throws naming "seed")
  /// @param seed  the digits of x_0
  AbOrbit(AbMap map, SeedDigits seed);
  /// The i-th base-r digit (i >= 1) of x_k: d_{k+i} (r-adic), d_{k+i} XOR d_k (tent).
  int digit(std::size_t k, std::size_t i);
  /// sign(x_k - p/q) in {-1, 0, +1} (1 <= q <= 2^20, 0 <= p < q; throws naming "q" or "p"), exact: digits are compared
  /// with those of p/q until they differ. Two equal rationals agree on every digit; the
  /// comparison stops after 2^21 + 128 equal digits, which by the Fine-Wilf bound proves
  /// equality for the rational seeds allowed (both expansions periodic with period <= 2^20).
  int compare(std::size_t k, std::uint64_t p, std::uint64_t q);
  /// x_k rounded to a double (its first ceil(64 / log2 r) digits; error < 1e-16).
  double value(std::size_t k);

 private:
  AbMap map_;
  SeedDigits seed_;
};

/// A code of `length` chips: c_k = readout(x_k), k = 0 .. length-1, of the orbit of `seed` under
/// spec's map (seed.base() must equal spec.base: throws naming "seed"). Binary codes (sign_cos)
/// are +-1 with zero imaginary part.
/// @param length  N in [1, 2^24] chips (throws naming "length")
Signal ab_code(const AbSpec& spec, SeedDigits seed, int length);

}  // namespace rnav::datalink
