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

#include "bus.hpp"
#include "free_input.hpp"
#include "free_node.hpp"
#include "uav_tma_node.hpp"

#include <deque>
#include <limits>
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

class UavTmaFreeNode : public FreeNode {
 public:
  UavTmaFreeNode(Bus& bus, const UavScenario& sc, const UavTmaFreeOptions& o);
  void flush() override;
  std::string summary() const override;

 private:
  void on_nav(const void* data, int size);
  void on_bearing(const void* data, int size);
  /// A batch of flight `f` arrived: a newer flight ends the current one.
  void enter_flight(const FlightKey& f);
  /// Batches: process every window both inputs hold.
  void drain_windows();
  /// What a batch that is the next of its flight does: it enters its flight (enter_flight), is
  /// queued on `q`, and every window both inputs hold is processed (drain_windows).
  template <class B> auto queue(std::deque<B>& q) {
    return [this, &q](B&& b) {
      enter_flight({b.header.realization, b.header.attempt});
      q.push_back(std::move(b));
      drain_windows();
    };
  }
  /// Samples: process every frame whose bearings are all in, given the latest times seen.
  void step_samples(bool end_of_input);

  Bus& bus_;
  UavScenario sc_;
  UavTmaFreeOptions o_;
  std::vector<std::unique_ptr<tma::TmaEstimator>> est_;
  InputForm form_;    // the form of every input (the first message sets it)
  FreeSkips skips_;   // resends and stale batches skipped, over both inputs
  FreeInput<observer_batch_t, observer_state_t> nav_in_;
  FreeInput<bearing_batch_t, bearing_t> bearing_in_;
  FlightKey flight_{-1, -1};
  std::deque<observer_batch_t> nav_q_;
  std::deque<bearing_batch_t> bearing_q_;
  std::int64_t seq_ = 0;
  std::deque<observer_state_t> frames_;             // single nav states not yet processed
  std::multimap<std::int64_t, bearing_t> bearings_;  // single bearings not yet processed
  std::int64_t last_nav_utime_ = std::numeric_limits<std::int64_t>::min();
  std::int64_t last_bearing_utime_ = std::numeric_limits<std::int64_t>::min();
  std::vector<tma_estimate_t> out_;
  long flights_ = 0, incomplete_flights_ = 0, frames_done_ = 0;
};

}  // namespace rnav
