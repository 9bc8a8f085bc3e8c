// Figures of merit of a code and of its waveform: the peak factor, the periodic auto- and
// cross-correlation, the power spectrum. Every sequence is one period of a periodic signal.
#pragma once

#include "sim/datalink/signal.hpp"

#include <vector>

namespace rnav::datalink {

/// Peak factor (peak-to-RMS ratio, crest factor of the complex envelope), dimensionless, >= 1:
///   PF = max_j |s_j| / sqrt( (1/L) sum_{j=0}^{L-1} |s_j|^2 ).
/// For a real (BPSK) signal |s_j| is the magnitude of the sample; a passband carrier multiplies
/// every PF by the same sqrt(2), so comparisons between codes are unchanged.
/// Throws std::invalid_argument naming "s" if s is empty or all zero.
double peak_factor(const Signal& s);

/// Periodic correlation of integer chip sequences, exactly, O(N^2):
///   R_ab(tau) = sum_{i=0}^{N-1} a_i b_{(i+tau) mod N},   tau = 0 .. N-1.
/// Throws std::invalid_argument naming "a" (empty) or "b" (length differs from a's).
std::vector<long> periodic_correlation_exact(const std::vector<int>& a, const std::vector<int>& b);

/// Periodic correlation of complex sequences through the FFT, O(N log N) (round-off ~1e-12 N):
///   R_ab(tau) = sum_{i=0}^{N-1} a_i conj(b_{(i+tau) mod N}),   tau = 0 .. N-1,
/// computed as  conj(R_ab) = IDFT( conj(A) B )  with A = DFT(a), B = DFT(b).
/// Throws std::invalid_argument naming "a" (empty) or "b" (length differs).
Signal periodic_correlation(const Signal& a, const Signal& b);

/// Power spectrum of one period of a periodic sampled signal, power per harmonic:
///   P_m = |S_m|^2 / L^2,   S_m = sum_j s_j e^{-2 pi i m j / L},   m = 0 .. L-1,
/// so that sum_m P_m = (1/L) sum_j |s_j|^2 (Parseval). Harmonic m is at m/L cycles per sample,
/// i.e. at f = m S / L chip rates for S samples per chip (m > L/2: negative, (m - L) S / L).
/// Throws std::invalid_argument naming "s" if empty.
std::vector<double> power_spectrum(const Signal& s);

/// The correlation peaks of a set of codes of one length, with each code's DFT computed once.
class CorrelationBank {
 public:
  /// @param codes  at least one code, all of the same length N >= 2; throws std::invalid_argument
  ///               naming "codes" otherwise.
  explicit CorrelationBank(const std::vector<Signal>& codes);
  /// max_{tau != 0} |R_aa(tau)| of code i [chip products, i.e. in units of one chip's energy].
  double max_offpeak_auto(int i) const;
  /// max_tau |R_ab(tau)| of codes i != j (same unit). Throws naming "j" if j == i or out of range.
  double max_cross(int i, int j) const;
  int size() const { return static_cast<int>(spectra_.size()); }

 private:
  Signal correlation(int i, int j) const;
  std::vector<Signal> spectra_;
};

}  // namespace rnav::datalink
