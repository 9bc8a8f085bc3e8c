// A family's codes by name, and the peak factor the data link takes from them.
//
// Families: "gold" (GoldFamily::preferred), "gold-qpsk" (two Gold codes on I and Q),
// "abR" / "tent" (Bernoulli-map binary codes, ab_codes.hpp), "abR-phase" / "tent-phase"
// (their polyphase readout). rnav_code_study and the data-link node draw codes the same way,
// so the link's peak factor is the study's number for the same family, length and filter.
#pragma once

#include "sim/datalink/signal.hpp"
#include "sim/datalink/waveform.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rnav::datalink {

/// One code of a family: its index in the family (Gold index, or the AB seed) and its chips.
struct FamilyCode {
  long index = 0;
  Signal chips;
};

/// The Gold degree n of a stored preferred pair for length N = 2^n - 1: 127 -> 7, 511 -> 9,
/// 1023 -> 10. Throws std::invalid_argument naming "length" for any other N.
int gold_degree_of_length(int length);

/// True for a family name family_codes() accepts.
bool known_family(const std::string& family);

/// `count` codes of `family` at length N.
/// gold, gold-qpsk: indices floor(s (N+2) / count), s = 0 .. count-1, spread evenly over the N+2
///   codes (count <= N+2); gold-qpsk's code i is (g_i + j g_{(i + (N+2)/2) mod (N+2)}) / sqrt(2).
/// AB families: the generic seeds seed0 .. seed0 + count - 1 (SeedDigits::generic).
/// @param family  as above (throws std::invalid_argument naming "family")
/// @param length  N: 127, 511 or 1023 for Gold families (throws naming "length"), [1, 2^24] for AB
/// @param count   [1, N+2] for Gold families, [1, 1e6] for AB (throws naming "count")
/// @param seed0   first AB seed, any value
std::vector<FamilyCode> family_codes(const std::string& family, int length, int count, std::uint64_t seed0);

/// The peak factor of a family's band-limited waveform: the q-quantile over `count` codes
/// (family_codes with seed0 = 1, rnav_code_study's default) of PF = max|s| / rms(s) of
/// bpsk_waveform(code, samples_per_chip, filter). Quantile as numpy's default (linear between
/// order statistics: position (count - 1) q of the sorted values), so q = 0.5 is the median
/// (the README's code-study table), q = 1 the worst code.
/// @param q  [0, 1] (throws std::invalid_argument naming "quantile"); other arguments as
///           family_codes and bpsk_waveform.
double family_peak_factor(const std::string& family, int length, const Filter& filter, double q, int count,
                          int samples_per_chip);

}  // namespace rnav::datalink
