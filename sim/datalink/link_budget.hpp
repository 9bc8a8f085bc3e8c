// The navigation data link's budget: from the transmitter's peak power to the
// probability that one navigation message is lost at slant range d. Pure functions, SI units.
//
// The chain, each step implemented under the equation it states (link_budget.cpp):
//
//   usable mean power   P_mean = P_peak / PF^2
//       The aircraft's amplifier is limited in peak envelope power P_peak [W]; a waveform of peak
//       factor PF (peak-to-RMS amplitude of its complex envelope after band-limiting,
//       code_metrics.hpp) can use at most P_peak / PF^2 on average.
//   wavelength          lambda = c / f
//   free-space loss     L_fs(d) = (4 pi d / lambda)^2                      (power ratio, >= 1 far out)
//   received power      C(d) = P_mean G_t G_r / (L_fs(d) L)
//   noise bandwidth     B_n = 2 B R_c        (B in chip rates: the band-limited BPSK spectrum spans
//                                              |f| <= B R_c about the carrier)
//   SNR in B_n          SNR(d) = C(d) / (k T0 F B_n)
//                              = P_mean G_t G_r lambda^2 / ((4 pi d)^2 k T0 F B_n L)
//   despreading         one data bit per code period of N chips: R_b = R_c / N; the correlator
//                       gains G_p = B_n / R_b = 2 B N, so Eb/N0 = SNR G_p = C / (k T0 F R_b)
//                       (Eb/N0 does not depend on B: the bandwidth acts only through PF)
//   bit error rate      BER = Q(sqrt(2 Eb/N0)) = erfc(sqrt(Eb/N0)) / 2      (coherent BPSK, AWGN)
//   message loss        p_loss = 1 - (1 - BER)^N_msg                          (no FEC: any wrong bit)
//
// Assumptions: free space (no multipath, fading, refraction or Earth curvature), the receiver
// matched to the band-limited waveform (no loss from the filter besides PF, no interference
// between bits: N >> 1), coherent BPSK data on the spreading code, independent bit errors,
// receiver noise k T0 F only (no antenna temperature).
#pragma once

#include "sim/datalink/datalink_options.hpp"

#include <string>

namespace rnav::datalink {

/// Speed of light in vacuum [m/s] (exact, SI).
inline constexpr double kSpeedOfLightMps = 299792458.0;
/// Boltzmann constant [J/K] (exact, SI 2019).
inline constexpr double kBoltzmannJpK = 1.380649e-23;

/// Q(x) = P(Z > x) for Z ~ N(0, 1) = erfc(x / sqrt 2) / 2.
double q_function(double x);
/// Free-space path loss L_fs = (4 pi d f / c)^2 as a power ratio.
/// @param range_m      d [m], finite, > 0
/// @param frequency_hz f [Hz], finite, > 0
/// Throws std::invalid_argument naming "range_m" or "frequency_hz".
double free_space_loss(double range_m, double frequency_hz);
/// Bit error rate of coherent BPSK in white Gaussian noise: Q(sqrt(2 Eb/N0)).
/// @param ebn0  Eb/N0 as a ratio (not dB), >= 0 (throws naming "ebn0"; +inf gives 0)
double ber_bpsk(double ebn0);
/// Probability that a message of `bits` bits has at least one wrong bit, bits independent:
/// 1 - (1 - ber)^bits, computed as -expm1(bits log1p(-ber)) (exact for tiny ber).
/// @param ber   [0, 1] (throws naming "ber"),  @param bits  >= 1 (throws naming "bits")
double message_loss(double ber, int bits);
/// 10 log10(x) and its inverse.
double to_db(double ratio);
double from_db(double db);

class LinkBudget {
 public:
  /// The budget of the scenario's `datalink` section (its keys' symbols: P_peak = peak_power_w,
  /// f = frequency_hz, G_t, G_r = tx_gain_dbi, rx_gain_dbi, F = noise_figure_db,
  /// T0 = noise_temperature_k, L = system_loss_db, R_c = chip_rate_hz, B = bandwidth_chips,
  /// N = code_length, N_msg = message_bits; units and defaults in datalink_options.hpp) with the
  /// waveform's peak factor PF [1] (peak/RMS amplitude, >= 1: datalink_peak_factor). The scenario
  /// checks its keys for users; this checks again what the budget needs (finite, P_peak, f, T0,
  /// R_c, B > 0, PF >= 1, N and N_msg >= 1, ...) and throws rnav::ConfigError naming the value
  /// ("datalink budget: peak_power_w = -1 W must be finite and in (0, 1000000000]"). The link's
  /// other keys (family, filter, ...) are not used here.
  LinkBudget(const DatalinkOptions& link, double peak_factor);

  /// P_mean = P_peak / PF^2 [W].
  double mean_power_w() const;
  /// lambda = c / f [m].
  double wavelength_m() const;
  /// B_n = 2 B R_c [Hz].
  double noise_bandwidth_hz() const;
  /// R_b = R_c / N [bit/s].
  double bit_rate_bps() const;
  /// G_p = B_n / R_b = 2 B N [1].
  double processing_gain() const;
  /// Received carrier power C(d) [W] at slant range d [m] (> 0, finite; throws naming "range_m").
  double received_power_w(double range_m) const;
  /// SNR(d) in the noise bandwidth B_n [ratio].
  double snr(double range_m) const;
  /// Eb/N0 at d [ratio] = SNR(d) G_p.
  double ebn0(double range_m) const;
  /// BER of one data bit at d.
  double ber(double range_m) const;
  /// Probability that one message is lost at slant range d [m]: what the data-link node draws.
  double p_loss(double range_m) const;
  /// The slant range [m] at which p_loss = p (p in (0, 1), throws naming "p"): p_loss grows
  /// monotonically with range, found by bisection on log d over [1e-3 m, 1e12 m] to 1e-12
  /// relative; the bound itself if p is not reached inside it.
  double range_for_p_loss(double p) const;
  /// One paragraph: PF, P_mean, Eb/N0 at 1 km, the ranges of 1 %, 50 % and 99 % loss.
  std::string describe() const;

 private:
  DatalinkOptions p_;
  double pf_ = 1;  // PF
  double ebn0_at_1m_ = 0;  // Eb/N0 at d = 1 m; Eb/N0(d) = ebn0_at_1m_ / d^2
};

}  // namespace rnav::datalink
