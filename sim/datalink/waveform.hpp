// BPSK (or, for complex chips, any phase-coded) waveform of a periodic code, band-limited by a
// zero-phase filter applied exactly in the frequency domain.
//
// Time is in chips (T = 1/Rc, Rc the chip rate) and frequency in chip rates (f T): a filter of
// bandwidth B = 1 passes |f| <= Rc. The code c_0 .. c_{N-1} repeats with period N T, so its
// waveform is a Fourier series with harmonics at f_m = m / N (m integer), and filtering is a
// product with H(f_m): periodic, no edge effects, no truncated impulse response.
#pragma once

#include "sim/datalink/signal.hpp"

#include <string>

namespace rnav::datalink {

/// A real, even, zero-phase frequency response H(f), f in chip rates.
class Filter {
 public:
  enum class Kind { none, brick_wall, raised_cosine };

  /// H(f) = 1 for every f: the unfiltered rectangular (NRZ) waveform.
  static Filter none();
  /// Ideal low-pass:  H(f) = 1 for |f| <= B, 0 for |f| > B (a harmonic exactly at B passes).
  /// @param bandwidth  B [chip rates], finite, in (0, 1000]; throws std::invalid_argument
  ///                   naming "bandwidth" otherwise.
  static Filter brick_wall(double bandwidth);
  /// Raised cosine with -6 dB frequency B and roll-off beta (for B = 1/(2T) = 0.5 the textbook
  /// Nyquist raised cosine of the chip rate):
  ///   H(f) = 1                                                  for |f| <= (1-beta) B
  ///        = 1/2 [1 + cos( pi (|f| - (1-beta) B) / (2 beta B) )] for (1-beta) B < |f| <= (1+beta) B
  ///        = 0                                                  for |f| > (1+beta) B
  /// so H((1-beta) B) = 1, H(B) = 1/2, H((1+beta) B) = 0.
  /// @param bandwidth  B [chip rates], finite, in (0, 1000]   (throws naming "bandwidth")
  /// @param rolloff    beta, dimensionless, in (0, 1]          (throws naming "rolloff")
  static Filter raised_cosine(double bandwidth, double rolloff);
  /// "none", "brick:B" or "rc:B:BETA" (B in chip rates), as name() writes; throws
  /// std::invalid_argument naming "filter" (unknown form, unreadable number) or the parameter.
  static Filter parse(const std::string& text);

  /// H(f), f in chip rates.
  double response(double f) const;
  /// The highest |f| [chip rates] with H(f) != 0: B (brick wall), (1+beta) B (raised cosine),
  /// infinity (none).
  double band_edge() const;
  Kind kind() const { return kind_; }
  /// B [chip rates] (infinity for none)
  double bandwidth() const;
  /// beta (0 unless raised cosine)
  double rolloff() const { return rolloff_; }
  /// "none", "brick:B", "rc:B:BETA" (shortest decimal text of the numbers).
  std::string name() const;

 private:
  Filter(Kind k, double b, double beta) : kind_(k), bandwidth_(b), rolloff_(beta) {}
  Kind kind_;
  double bandwidth_;
  double rolloff_;
};

/// One period (N S samples, t_j = j T / S) of the waveform of `chips` through `filter`.
///
/// Unfiltered (Filter::none()): the rectangular NRZ waveform, s_j = c_{floor(j / S)}.
/// Filtered: the exact continuous-time NRZ waveform s(t) = c_k for k T <= t < (k+1) T, filtered,
/// then sampled. Its Fourier coefficients (period N T) are
///   a_m = (1/N) C_{m mod N} e^{-i pi m / N} sinc(m / N),   C_q = sum_k c_k e^{-2 pi i q k / N},
///   sinc(x) = sin(pi x) / (pi x),
/// and the filtered samples are  y_j = sum_m H(m/N) a_m e^{2 pi i m j / (N S)},  an inverse DFT of
/// length N S (no aliasing, because H vanishes at |f| >= S/2, which is checked).
/// @param chips             N >= 1 chips (+-1 for BPSK; any complex values, e.g. e^{i phi})
/// @param samples_per_chip  S, in [1, 4096]; with a filter, its band_edge() must be < S/2
///                          (throws std::invalid_argument naming "samples_per_chip")
/// @param filter            as above
Signal bpsk_waveform(const Signal& chips, int samples_per_chip, const Filter& filter);

/// Filter one period of a periodic sampled signal x (L samples, S per chip) in the frequency
/// domain: y = IDFT( H(f_q) DFT(x)_q ), f_q = m_q S / L chip rates with m_q = q for q <= L/2 and
/// q - L above (the harmonic's signed frequency).
/// @param x                 L >= 1 samples (throws naming "x" if empty)
/// @param samples_per_chip  S >= 1 [samples per chip] (throws naming "samples_per_chip")
Signal apply_filter(const Signal& x, int samples_per_chip, const Filter& filter);

}  // namespace rnav::datalink
