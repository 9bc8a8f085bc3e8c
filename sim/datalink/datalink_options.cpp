#include "sim/datalink/datalink_options.hpp"

namespace rnav {

void check_datalink(const DatalinkOptions& d) {
  if (d.code_length != 127 && d.code_length != 511 && d.code_length != 1023)
    throw ConfigError("scenario key 'datalink.code_length' = " + std::to_string(d.code_length) +
                      " must be 127, 511 or 1023 (the Gold lengths with a stored preferred pair)");
  if ((d.family == "gold" || d.family == "gold-qpsk") && d.pf_codes > d.code_length + 2)
    throw ConfigError("scenario key 'datalink.pf_codes' = " + std::to_string(d.pf_codes) + " exceeds the Gold family's " +
                      std::to_string(d.code_length + 2) + " codes at datalink.code_length = " + std::to_string(d.code_length));
  const double edge = d.filter == "rc" ? (1 + d.rolloff) * d.bandwidth_chips : d.bandwidth_chips;
  if (!(edge < 0.5 * static_cast<double>(d.samples_per_chip)))
    throw ConfigError("scenario key 'datalink.samples_per_chip' = " + std::to_string(d.samples_per_chip) +
                      ": the filter's band edge " + value_text(edge) + " chip rates must lie below half of it");
}

double message_air_time_s(const DatalinkOptions& d) {
  return static_cast<double>(d.message_bits) * static_cast<double>(d.code_length) / d.chip_rate_hz;
}

}  // namespace rnav
