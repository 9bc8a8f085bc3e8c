#include "sim/datalink/nav_link.hpp"

#include "sim/datalink/code_family.hpp"
#include "common/io/config.hpp"

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

double datalink_peak_factor(const DatalinkOptions& d) {
  try {
    return family_peak_factor(d.family, static_cast<int>(d.code_length), datalink_filter(d), d.pf_quantile,
                              static_cast<int>(d.pf_codes), static_cast<int>(d.samples_per_chip));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("scenario section 'datalink': cannot compute the peak factor: ") + e.what());
  }
}

NavLink::NavLink(const DatalinkOptions& d, const SiteContext& site)
    : NavLink(LinkBudget(d, datalink_peak_factor(d)), site.radar_site()) {}

NavLink::NavLink(const LinkBudget& budget, const Geodetic& receiver) : budget_(budget), receiver_(receiver, 0.0) {}

double NavLink::range_m(const nav_solution_t& n) const {
  return receiver_.from_geodetic(Geodetic{n.lat_deg, n.lon_deg, n.h_m}).norm();
}

}  // namespace rnav::datalink
