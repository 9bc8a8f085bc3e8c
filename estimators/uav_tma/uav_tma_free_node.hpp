// The azimuth-only estimators without the lock-step clock: UAV_NAV and UAV_BEARING as they
// come, in either of two forms (all inputs in the same form, see free_input.hpp):
//  - lock-step batches (a recorded lock-step run replayed by lcm-logplayer): window w is
//    processed once both inputs' batches of w are in, as the lock-step node does it, and
//    UAV_TMA is published as that window's batch: the lock-step run's own messages, byte for
//    byte. A new (realization, attempt) is a new flight; an incomplete one is counted.
//  - one nav state / one bearing per message (a real-time run, or a real UAV and sensor): a
//    frame (the nav state at time t and the bearings at t) is processed once its bearings are
//    all in: after a bearing later than t, or a nav state at least bearing_lateness_s after t
//    (the sensor is assumed never to lag the UAV's navigation by more; frames without a
//    detection wait for it). One tma_estimate_t per initialised estimator is published per
//    frame on UAV_TMA. Samples must run forward in time; a bearing at a time with no nav state
//    is an error naming it.
#pragma once

#include "common/node/bus.hpp"
#include "common/node/paired_free_node.hpp"
#include "estimators/uav_tma/uav_tma_node.hpp"

#include <deque>
#include <map>

namespace rnav {

struct UavTmaFreeOptions {
  /// [s] >= 0, default 1: how far the bearings may lag the nav states when both come as single
  /// messages (see the file comment).
  double bearing_lateness_s = 1.0;
  /// Ensemble seed of the recorded run, default 1: with the flight's realization it selects the
  /// particle filter's random stream ("pf" in tma.estimators), so a lock-step run's pf estimates
  /// are reproduced from its log when this is that run's --seed. The other estimators draw nothing.
  long long seed = 1;
};

class UavTmaFreeNode : public PairedFreeNode<observer_batch_t, observer_state_t, bearing_batch_t, bearing_t> {
 public:
  UavTmaFreeNode(Bus& bus, const TmaOptions& tma, const UavContext& ctx, const UavTmaFreeOptions& o);

 private:
  void on_window(const observer_batch_t& nav, const bearing_batch_t& bearings) override;
  void on_sample_a(const observer_state_t& o) override;
  void on_sample_b(const bearing_t& b) override;
  void on_end_of_samples() override { step_samples(true); }
  void on_new_flight(const FlightKey& f) override;
  std::string output_summary() const override;
  /// Samples: process every frame whose bearings are all in, given the latest times seen.
  void step_samples(bool end_of_input);

  TmaOptions tma_;
  UavContext ctx_;
  UavTmaFreeOptions o_;
  std::vector<std::unique_ptr<tma::TmaEstimator>> est_;
  std::int64_t seq_ = 0;
  std::deque<observer_state_t> frames_;             // single nav states not yet processed
  std::multimap<std::int64_t, bearing_t> bearings_;  // single bearings not yet processed
  ForwardTimes nav_times_;      // [us] the single nav states' utime
  ForwardTimes bearing_times_;  // [us] the single bearings' utime
  std::vector<tma_estimate_t> out_;
  long frames_done_ = 0;
};

}  // namespace rnav
