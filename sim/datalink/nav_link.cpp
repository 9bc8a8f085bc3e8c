#include "nav_link.hpp"

#include "code_family.hpp"
#include "config.hpp"

#include <stdexcept>

namespace rnav::datalink {

Filter datalink_filter(const DatalinkOptions& d) {
  try {
    if (d.filter == "brick") return Filter::brick_wall(d.bandwidth_chips);
    if (d.filter == "rc") return Filter::raised_cosine(d.bandwidth_chips, d.rolloff);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("scenario key 'datalink.bandwidth_chips' or 'datalink.rolloff': ") + e.what());
  }
  throw ConfigError("scenario key 'datalink.filter': '" + d.filter + "' is not one of rc, brick");
}

LinkBudgetParams link_budget_params(const DatalinkOptions& d, double peak_factor) {
  LinkBudgetParams p;
  p.peak_power_w = d.peak_power_w;
  p.peak_factor = peak_factor;
  p.frequency_hz = d.frequency_hz;
  p.tx_gain_dbi = d.tx_gain_dbi;
  p.rx_gain_dbi = d.rx_gain_dbi;
  p.noise_figure_db = d.noise_figure_db;
  p.noise_temperature_k = d.noise_temperature_k;
  p.system_loss_db = d.system_loss_db;
  p.chip_rate_hz = d.chip_rate_hz;
  p.bandwidth_chips = d.bandwidth_chips;
  p.code_length = static_cast<int>(d.code_length);
  p.message_bits = static_cast<int>(d.message_bits);
  return p;
}

double datalink_peak_factor(const DatalinkOptions& d) {
  try {
    return family_peak_factor(d.family, static_cast<int>(d.code_length), datalink_filter(d), d.pf_quantile,
                              static_cast<int>(d.pf_codes), static_cast<int>(d.samples_per_chip));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("scenario section 'datalink': cannot compute the peak factor: ") + e.what());
  }
}

NavLink::NavLink(const Scenario& sc)
    : NavLink(LinkBudget(link_budget_params(sc.datalink, datalink_peak_factor(sc.datalink))), sc.radar_site()) {}

NavLink::NavLink(const LinkBudget& budget, const Geodetic& receiver) : budget_(budget), receiver_(receiver, 0.0) {}

double NavLink::range_m(const nav_solution_t& n) const {
  return receiver_.from_geodetic(Geodetic{n.lat_deg, n.lon_deg, n.h_m}).norm();
}

}  // namespace rnav::datalink
