#include "sim/datalink/link_budget.hpp"

#include "common/io/config.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rnav::datalink {

namespace {

// A finite value in [lo, hi] (lo_open: lo itself excluded), else a ConfigError naming the key.
void check(const char* key, double x, double lo, double hi, bool lo_open, const char* unit) {
  const bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && x <= hi;
  if (!ok)
    throw ConfigError(std::string("datalink budget: ") + key + " = " + value_text(x) + " " + unit + " must be finite and in " +
                      (lo_open ? "(" : "[") + value_text(lo) + ", " + value_text(hi) + "]");
}

void check_range(double range_m) {
  if (!std::isfinite(range_m) || range_m <= 0)
    throw std::invalid_argument("range_m: " + value_text(range_m) + " m must be finite and > 0");
}

}  // namespace

// Q(x) = (1/sqrt(2 pi)) int_x^inf exp(-t^2/2) dt = erfc(x / sqrt(2)) / 2
double q_function(double x) { return 0.5 * std::erfc(x / std::sqrt(2.0)); }

// L_fs = (4 pi d / lambda)^2 = (4 pi d f / c)^2
double free_space_loss(double range_m, double frequency_hz) {
  check_range(range_m);
  if (!std::isfinite(frequency_hz) || frequency_hz <= 0)
    throw std::invalid_argument("frequency_hz: " + value_text(frequency_hz) + " Hz must be finite and > 0");
  const double a = 4.0 * M_PI * range_m * frequency_hz / kSpeedOfLightMps;
  return a * a;
}

// BER = Q(sqrt(2 Eb/N0)) = erfc(sqrt(Eb/N0)) / 2   (coherent BPSK, AWGN)
double ber_bpsk(double ebn0) {
  if (std::isnan(ebn0) || ebn0 < 0) throw std::invalid_argument("ebn0: " + value_text(ebn0) + " must be >= 0 (a ratio, not dB)");
  return 0.5 * std::erfc(std::sqrt(ebn0));
}

// p_loss = 1 - (1 - BER)^N_msg = -expm1(N_msg log1p(-BER))
double message_loss(double ber, int bits) {
  if (!(ber >= 0 && ber <= 1)) throw std::invalid_argument("ber: " + value_text(ber) + " must lie in [0, 1]");
  if (bits < 1) throw std::invalid_argument("bits: " + std::to_string(bits) + " must be >= 1");
  if (ber == 1) return 1.0;
  return -std::expm1(static_cast<double>(bits) * std::log1p(-ber));
}

double to_db(double ratio) { return 10.0 * std::log10(ratio); }
double from_db(double db) { return std::pow(10.0, db / 10.0); }

LinkBudget::LinkBudget(const DatalinkOptions& p, double peak_factor) : p_(p), pf_(peak_factor) {
  check("peak_power_w", p.peak_power_w, 0, 1e9, true, "W");
  check("peak_factor", peak_factor, 1, 1e6, false, "(peak/RMS)");
  check("frequency_hz", p.frequency_hz, 1e6, 1e12, false, "Hz");
  check("tx_gain_dbi", p.tx_gain_dbi, -50, 60, false, "dBi");
  check("rx_gain_dbi", p.rx_gain_dbi, -50, 60, false, "dBi");
  check("noise_figure_db", p.noise_figure_db, 0, 40, false, "dB");
  check("noise_temperature_k", p.noise_temperature_k, 0, 1e5, true, "K");
  check("system_loss_db", p.system_loss_db, 0, 200, false, "dB");
  check("chip_rate_hz", p.chip_rate_hz, 0, 1e11, true, "chips/s");
  check("bandwidth_chips", p.bandwidth_chips, 0, 1000, true, "chip rates");
  check("code_length", static_cast<double>(p.code_length), 1, 1 << 24, false, "chips");
  check("message_bits", static_cast<double>(p.message_bits), 1, 1e7, false, "bits");
  // Eb/N0(d) = C(d) / (k T0 F R_b),  C(d) = P_mean G_t G_r lambda^2 / ((4 pi d)^2 L):
  // Eb/N0 at d = 1 m, so that Eb/N0(d) = ebn0_at_1m_ / d^2.
  ebn0_at_1m_ = received_power_w(1.0) / (kBoltzmannJpK * p.noise_temperature_k * from_db(p.noise_figure_db) * bit_rate_bps());
}

// P_mean = P_peak / PF^2
double LinkBudget::mean_power_w() const { return p_.peak_power_w / (pf_ * pf_); }

// lambda = c / f
double LinkBudget::wavelength_m() const { return kSpeedOfLightMps / p_.frequency_hz; }

// B_n = 2 B R_c
double LinkBudget::noise_bandwidth_hz() const { return 2.0 * p_.bandwidth_chips * p_.chip_rate_hz; }

// R_b = R_c / N
double LinkBudget::bit_rate_bps() const { return p_.chip_rate_hz / static_cast<double>(p_.code_length); }

// G_p = B_n / R_b = 2 B N
double LinkBudget::processing_gain() const { return noise_bandwidth_hz() / bit_rate_bps(); }

// C(d) = P_mean G_t G_r / (L_fs(d) L) = P_mean G_t G_r lambda^2 / ((4 pi d)^2 L)
double LinkBudget::received_power_w(double range_m) const {
  return mean_power_w() * from_db(p_.tx_gain_dbi) * from_db(p_.rx_gain_dbi) /
         (free_space_loss(range_m, p_.frequency_hz) * from_db(p_.system_loss_db));
}

// SNR(d) = C(d) / (k T0 F B_n) = P_mean G_t G_r lambda^2 / ((4 pi d)^2 k T0 F B_n L)
double LinkBudget::snr(double range_m) const {
  return received_power_w(range_m) /
         (kBoltzmannJpK * p_.noise_temperature_k * from_db(p_.noise_figure_db) * noise_bandwidth_hz());
}

// Eb/N0(d) = SNR(d) G_p = C(d) / (k T0 F R_b); the constructor's ebn0_at_1m_ / d^2 is the same
// number (C falls as 1/d^2), evaluated once.
double LinkBudget::ebn0(double range_m) const {
  check_range(range_m);
  return ebn0_at_1m_ / (range_m * range_m);
}

// BER(d) = Q(sqrt(2 Eb/N0(d)))
double LinkBudget::ber(double range_m) const { return ber_bpsk(ebn0(range_m)); }

// p_loss(d) = 1 - (1 - BER(d))^N_msg
double LinkBudget::p_loss(double range_m) const { return message_loss(ber(range_m), static_cast<int>(p_.message_bits)); }

double LinkBudget::range_for_p_loss(double p) const {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("p: " + value_text(p) + " must lie in (0, 1)");
  double lo = std::log(1e-3), hi = std::log(1e12);
  if (p_loss(std::exp(lo)) >= p) return std::exp(lo);
  if (p_loss(std::exp(hi)) <= p) return std::exp(hi);
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi);
    (p_loss(std::exp(mid)) < p ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

std::string LinkBudget::describe() const {
  std::ostringstream o;
  o.precision(4);
  o << "P_peak " << p_.peak_power_w << " W, PF " << pf_ << " -> P_mean = P_peak/PF^2 = " << mean_power_w()
    << " W; f " << p_.frequency_hz << " Hz, R_c " << p_.chip_rate_hz << " chips/s, N " << p_.code_length << " (R_b "
    << bit_rate_bps() << " bit/s), B_n " << noise_bandwidth_hz() << " Hz; at 1 km: SNR " << to_db(snr(1000)) << " dB, Eb/N0 "
    << to_db(ebn0(1000)) << " dB; message (" << p_.message_bits << " bits) lost with p = 0.01 / 0.5 / 0.99 at "
    << range_for_p_loss(0.01) << " / " << range_for_p_loss(0.5) << " / " << range_for_p_loss(0.99) << " m";
  return o.str();
}

}  // namespace rnav::datalink
