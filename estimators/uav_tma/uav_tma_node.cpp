#include "estimators/uav_tma/uav_tma_node.hpp"

#include <rnav/bearing_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <algorithm>
#include <map>

namespace rnav {

UavTmaNode::UavTmaNode(Bus& bus, const TmaOptions& o, const UavContext& ctx)
    : LockstepNode(bus, "uav_tma", ctx.runner.peer_timeout_s), o_(o), ctx_(ctx) {
  add_input<observer_batch_t>(ch::kUavNav);
  add_input<bearing_batch_t>(ch::kUavBearing);
}

void UavTmaNode::reset(const sim_window_t& w) {
  est_ = tma::make_estimators(o_, static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization));
}

int UavTmaNode::process(const sim_window_t&) {
  tma_batch_t out;
  tma_window(est_, ctx_.runner.epoch_utime, input<observer_batch_t>(ch::kUavNav),
             input<bearing_batch_t>(ch::kUavBearing), out.estimates);
  out.n = static_cast<int>(out.estimates.size());
  publish_batch(ch::kUavTma, out);
  return out.n;
}

void tma_window(std::vector<std::unique_ptr<tma::TmaEstimator>>& est, std::int64_t epoch_utime,
                const observer_batch_t& nav, const bearing_batch_t& bearings, std::vector<tma_estimate_t>& out) {
  std::multimap<std::int64_t, const bearing_t*> by_time;
  for (const auto& b : bearings.bearings) by_time.emplace(b.utime, &b);
  std::vector<const bearing_t*> frame;
  for (const auto& o : nav.states) {
    frame.clear();
    const auto range = by_time.equal_range(o.utime);
    for (auto it = range.first; it != range.second; ++it) frame.push_back(it->second);
    process_tma_frame(est, epoch_utime, o, frame, out);
  }
  for (const auto& b : bearings.bearings)
    if (std::none_of(nav.states.begin(), nav.states.end(),
                     [&](const observer_state_t& o) { return o.utime == b.utime; }))
      throw std::runtime_error("UAV_BEARING at utime " + std::to_string(b.utime) +
                               " has no UAV_NAV solution at its time");
}

}  // namespace rnav
