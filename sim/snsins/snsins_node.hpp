// Node "snsins": turns TRUTH_AIRCRAFT into the navigation solution the ground receives
// (NAV_SOLUTION): WGS84 position and NED velocity with SnsinsErrorModel errors, sampled at the
// link times t = link_phase_s + k link_period_s (validity), delivered at t + latency_s.
// A window's batch holds the solutions whose arrival time lies in the window. With
// datalink.enabled it publishes on NAV_SOLUTION_TX instead (what the aircraft sends; the node
// "datalink" passes on what survives the link).
#pragma once

#include "common/node/lockstep_node.hpp"
#include "common/node/site_context.hpp"
#include "sim/snsins/snsins_error_model.hpp"

#include <rnav/nav_solution_t.hpp>

#include <deque>
#include <optional>

namespace rnav {

class SnsinsNode : public LockstepNode {
 public:
  /// @param via_datalink  the data link is modelled (datalink.enabled): publish on
  ///                      NAV_SOLUTION_TX instead of NAV_SOLUTION
  SnsinsNode(Bus& bus, const SnsinsOptions& o, const SiteContext& site, bool via_datalink);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  bool in_dropout(double t_s) const;
  SnsinsOptions o_;
  SiteContext site_;
  bool via_datalink_;
  LocalLevelFrame frame_L_;
  SnsinsErrorModel model_;
  std::optional<Rng> rng_;
  std::deque<nav_solution_t> pending_;  // generated, not yet arrived
};

}  // namespace rnav
