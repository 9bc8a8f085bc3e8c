// The radar bias estimator without the lock-step clock: PRL_APOI and NAV_SOLUTION as they come,
// in either of two forms (all inputs in the same form):
//  - lock-step batches (a recorded lock-step run replayed by lcm-logplayer): window w is
//    processed once both inputs' batches of w are in, exactly as the lock-step node does it, and
//    PRL_BIAS and PRL_TOI are published as batches of that window: the lock-step run's own
//    output messages, byte for byte. A new (realization, attempt) is a new flight; a flight left
//    incomplete (a failed attempt) is reported in the summary, not processed further.
//  - one plot / one solution per message (a real-time run, or a real radar and receiver): one
//    PRL_BIAS estimate and one PRL_TOI plot per plot, as soon as the plot's nav decision is
//    final. NavBuffer::decide needs "every solution that reached the ground before now has
//    arrived"; `now` is the latest solution's link_utime + 1 us (solutions arrive in link order),
//    and, while the nav link is silent (a drop-out), the latest plot's utime less nav_lateness_s:
//    the nav link is assumed never to lag the radar by more. Samples must run forward in time
//    (a step back is an error naming the channel: restart the node for a new flight).
#pragma once

#include "free_input.hpp"
#include "free_node.hpp"
#include "bus.hpp"
#include "prl_bias_stream.hpp"

#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

#include <cstdint>
#include <deque>
#include <limits>

namespace rnav {

struct PrlBiasFreeOptions {
  /// [s] >= 0, default 1: how far the nav link may lag the radar when both send single
  /// messages (see the file comment). Larger only delays the estimates; smaller than the real
  /// lag can decide a drop-out where a solution was still on its way.
  double nav_lateness_s = 1.0;
};

class PrlBiasFreeNode : public FreeNode {
 public:
  PrlBiasFreeNode(Bus& bus, const Scenario& sc, const PrlBiasFreeOptions& o);
  void flush() override;
  std::string summary() const override;

 private:
  void on_apoi(const void* data, int size);
  void on_nav(const void* data, int size);
  /// A batch of flight `f` arrived: a newer flight ends the current one.
  void enter_flight(const FlightKey& f);
  /// What a batch that is the next of its flight does: it enters its flight (enter_flight), is
  /// queued on `q`, and every window both inputs hold is processed (drain_windows).
  template <class B> auto queue(std::deque<B>& q) {
    return [this, &q](B&& b) {
      enter_flight({b.header.realization, b.header.attempt});
      q.push_back(std::move(b));
      drain_windows();
    };
  }
  /// Batches: process every window both inputs hold.
  void drain_windows();
  /// Samples: process what is decided by `now_utime` and publish one message per plot.
  void step_samples(std::int64_t now_utime);

  Bus& bus_;
  PrlBiasFreeOptions o_;
  PrlBiasStream stream_;
  InputForm form_;    // the form of every input (the first message sets it)
  FreeSkips skips_;   // resends and stale batches skipped, over both inputs
  FreeInput<prl_plot_batch_t, prl_plot_t> apoi_in_;
  FreeInput<nav_batch_t, nav_solution_t> nav_in_;
  FlightKey flight_{-1, -1};
  std::deque<prl_plot_batch_t> apoi_q_;  // batches of the current flight not yet processed
  std::deque<nav_batch_t> nav_q_;
  std::int64_t bias_seq_ = 0, toi_seq_ = 0;
  std::int64_t nav_known_ = std::numeric_limits<std::int64_t>::min();  // [us] see file comment
  std::int64_t last_plot_utime_ = std::numeric_limits<std::int64_t>::min();
  std::int64_t last_nav_link_ = std::numeric_limits<std::int64_t>::min();
  std::vector<PrlBiasEstimator::Output> out_;
  long flights_ = 0, incomplete_flights_ = 0, published_ = 0;
};

}  // namespace rnav
