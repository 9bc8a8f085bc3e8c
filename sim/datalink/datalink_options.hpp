// Options of the navigation data link (scenario section "datalink"), with their keys and checks.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// The navigation data link from the aircraft to the ground receiver at the radar
/// (sim/datalink/link_budget.hpp has the equations). Off by default: snsins then publishes
/// NAV_SOLUTION itself, as before. On: snsins publishes what the aircraft sends on
/// NAV_SOLUTION_TX and the node "datalink" republishes on NAV_SOLUTION the messages that survive,
/// each lost with probability p_loss(d) at the slant range d from the nav solution's position to
/// the radar antenna. The transmitter is peak-power limited: P_mean = peak_power_w / PF^2, PF the
/// family's peak factor for this code length and filter, computed at start-up.
struct DatalinkOptions {
  bool enabled = false;           ///< model the link (adds the node "datalink")
  double peak_power_w = 1.0;      ///< [W] transmitter peak envelope power, [1e-15, 1e9]
  /// Spreading-code family: "gold", "gold-qpsk" (Gold codes on I and Q), "ab2", "ab3", "tent"
  /// (binary Bernoulli-map AB codes), "ab2-phase", "ab3-phase", "tent-phase" (polyphase AB codes);
  /// see sim/datalink/ab_codes.hpp and the README's code study.
  std::string family = "gold";
  long code_length = 127;         ///< [chips] per data bit: 127, 511 or 1023
  std::string filter = "rc";      ///< band-limiting filter: "rc" (raised cosine) or "brick" (ideal low-pass)
  double bandwidth_chips = 0.5;   ///< [chip rates] B: the filter's -6 dB (rc) or cut-off (brick) frequency, [1e-3, 100]
  double rolloff = 0.25;          ///< [1] raised-cosine roll-off beta, [1e-3, 1] (unused by "brick")
  /// [1] which peak factor of the family the transmitter must allow for: this quantile of PF over
  /// pf_codes codes (0.5: the median code, the code study's figure; 1: the worst), [0, 1]
  double pf_quantile = 0.5;
  long pf_codes = 129;            ///< codes the PF quantile is taken over, [2, 4096] (Gold: at most N + 2)
  long samples_per_chip = 24;     ///< waveform samples per chip for the PF, [4, 256]; the band edge must lie below half of it
  double chip_rate_hz = 10.16e6;  ///< [chips/s] R_c, [1, 1e11]; bit rate R_c / code_length (80 kbit/s at 127)
  double frequency_hz = 1.0e9;    ///< [Hz] carrier, [1e6, 1e12]
  double tx_gain_dbi = 0;         ///< [dBi] aircraft antenna gain towards the ground, [-50, 60]
  double rx_gain_dbi = 3;         ///< [dBi] ground antenna gain, [-50, 60]
  double noise_figure_db = 5;     ///< [dB] ground receiver noise figure, [0, 40]
  double noise_temperature_k = 290;  ///< [K] reference noise temperature T0, [1e-3, 1e5]
  double system_loss_db = 10;     ///< [dB] cables, antenna pattern, implementation and a fading margin, [0, 200]
  /// [bits] per navigation message (no FEC: lost if any bit is wrong), [1, 1e7]; its air time
  /// message_bits code_length / chip_rate_hz must not exceed snsins.link_period_s
  long message_bits = 256;
};
/// The section's combinations of keys (checked whether or not the link is enabled, so a file
/// that enables it later is already known to be consistent); ConfigError naming the key.
void check_datalink(const DatalinkOptions& d);

/// [s] one message's air time: message_bits code_length / chip_rate_hz.
double message_air_time_s(const DatalinkOptions& d);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(DatalinkOptions& o, V& v) {
  v.flag("enabled", o.enabled);
  v.num("peak_power_w", o.peak_power_w, 1e-15, 1e9);
  v.choice("family", o.family, {"gold", "gold-qpsk", "ab2", "ab3", "tent", "ab2-phase", "ab3-phase", "tent-phase"});
  v.integer("code_length", o.code_length, 127, 1023);
  v.choice("filter", o.filter, {"rc", "brick"});
  v.num("bandwidth_chips", o.bandwidth_chips, 1e-3, 100);
  v.num("rolloff", o.rolloff, 1e-3, 1);
  v.num("pf_quantile", o.pf_quantile, 0, 1);
  v.integer("pf_codes", o.pf_codes, 2, 4096);
  v.integer("samples_per_chip", o.samples_per_chip, 4, 256);
  v.num("chip_rate_hz", o.chip_rate_hz, 1, 1e11);
  v.num("frequency_hz", o.frequency_hz, 1e6, 1e12);
  v.num("tx_gain_dbi", o.tx_gain_dbi, -50, 60);
  v.num("rx_gain_dbi", o.rx_gain_dbi, -50, 60);
  v.num("noise_figure_db", o.noise_figure_db, 0, 40);
  v.num("noise_temperature_k", o.noise_temperature_k, 1e-3, 1e5);
  v.num("system_loss_db", o.system_loss_db, 0, 200);
  v.integer("message_bits", o.message_bits, 1, 10000000);
}

}  // namespace options_io
}  // namespace rnav
