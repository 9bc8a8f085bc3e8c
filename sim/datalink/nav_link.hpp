// The data link applied to navigation messages: the link budget of a
// scenario's `datalink` section, the slant range from a message's position to the ground
// receiver at the radar antenna, and each message's fate from one uniform draw.
#pragma once

#include "common/physics/frames.hpp"
#include "sim/datalink/link_budget.hpp"
#include "common/node/site_context.hpp"
#include "sim/datalink/waveform.hpp"

#include <rnav/nav_solution_t.hpp>

namespace rnav::datalink {

/// datalink.filter, bandwidth_chips, rolloff as a Filter ("rc": raised cosine, "brick": ideal).
Filter datalink_filter(const DatalinkOptions& d);
/// The family's PF for the scenario's code length and filter: family_peak_factor at
/// datalink.pf_quantile over datalink.pf_codes codes. Throws ConfigError naming "datalink".
double datalink_peak_factor(const DatalinkOptions& d);

class NavLink {
 public:
  /// The scenario's link: PF computed from the family at start-up (datalink_peak_factor), the
  /// receiver at the radar antenna (SiteContext::radar_site). Throws ConfigError on bad keys.
  NavLink(const DatalinkOptions& d, const SiteContext& site);
  /// A given budget and receiver position (tests).
  NavLink(const LinkBudget& budget, const Geodetic& receiver);

  const LinkBudget& budget() const { return budget_; }
  /// Slant range [m] from the solution's WGS84 position (lat_deg, lon_deg, h_m) to the receiver.
  /// The transmitted solution's position, not the truth: they differ by the nav error (about
  /// 2 m), which moves p_loss by less than 0.001 dB of SNR at the ranges of an approach.
  double range_m(const nav_solution_t& n) const;
  /// Whether a message at slant range d [m] is lost, given u uniform in [0, 1): u < p_loss(d).
  /// One draw per message, whatever its fate, so the stream stays aligned across settings.
  bool lost(double range_m, double u) const { return u < budget_.p_loss(range_m); }

 private:
  LinkBudget budget_;
  LocalLevelFrame receiver_;  // origin at the receiver antenna
};

}  // namespace rnav::datalink
