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

#include "common/node/bus.hpp"
#include "common/node/paired_free_node.hpp"
#include "estimators/prl_bias/prl_bias_stream.hpp"

#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

#include <cstdint>
#include <limits>

namespace rnav {

struct PrlBiasFreeOptions {
  /// [s] >= 0, default 1: how far the nav link may lag the radar when both send single
  /// messages (see the file comment). Larger only delays the estimates; smaller than the real
  /// lag can decide a drop-out where a solution was still on its way.
  double nav_lateness_s = 1.0;
};

class PrlBiasFreeNode : public PairedFreeNode<prl_plot_batch_t, prl_plot_t, nav_batch_t, nav_solution_t> {
 public:
  PrlBiasFreeNode(Bus& bus, const PrlBiasOptions& bias, const SiteContext& site, const PrlBiasFreeOptions& o);

 private:
  void on_window(const prl_plot_batch_t& apoi, const nav_batch_t& nav) override;
  void on_sample_a(const prl_plot_t& p) override;
  void on_sample_b(const nav_solution_t& n) override;
  void on_end_of_samples() override;
  void on_new_flight(const FlightKey& f) override;
  bool holds_undecided() const override { return stream_.pending() > 0; }
  std::string output_summary() const override;
  /// Samples: process what is decided by `now_utime` and publish one message per plot.
  void step_samples(std::int64_t now_utime);

  PrlBiasFreeOptions o_;
  PrlBiasStream stream_;
  std::int64_t bias_seq_ = 0, toi_seq_ = 0;
  std::int64_t nav_known_ = std::numeric_limits<std::int64_t>::min();  // [us] see file comment
  ForwardTimes plot_times_;  // [us] the single plots' utime
  ForwardTimes nav_links_;   // [us] the single solutions' link_utime
  std::vector<PrlBiasEstimator::Output> out_;
  long published_ = 0;
};

}  // namespace rnav
