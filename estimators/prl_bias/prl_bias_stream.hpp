// The estimator's scheduling of plots against navigation solutions, with no transport: plots
// queue until the nav decision for their time is final (NavBuffer::decide), then pass through
// PrlBiasEstimator in plot order. Shared by the lock-step node (prl_bias_node) and the
// free-running node (prl_bias_free_node), so both give the same estimates for the same inputs.
#pragma once

#include "estimators/prl_bias/prl_bias_estimator.hpp"
#include "common/node/site_context.hpp"

#include <rnav/nav_solution_t.hpp>

#include <deque>
#include <vector>

namespace rnav {

class PrlBiasStream {
 public:
  PrlBiasStream(const PrlBiasOptions& o, const SiteContext& site);
  /// Forget every plot, solution and estimate (a new flight or realization).
  void reset();
  /// A radar plot (plots in increasing utime).
  void add_plot(const prl_plot_t& plot) { pending_.push_back(plot); }
  /// A received navigation solution (in increasing link_utime).
  void add_nav(const nav_solution_t& nav);
  /// Process, in order, every pending plot whose nav decision is final given that every
  /// solution that reached the ground before `now_utime` [us] has been added; the first plot
  /// still waiting stops it. Outputs are appended to `out`.
  void process_ready(std::int64_t now_utime, std::vector<PrlBiasEstimator::Output>& out);
  /// Plots not yet processed (waiting for their nav decision).
  std::size_t pending() const { return pending_.size(); }
  /// The first waiting plot (pending() > 0).
  const prl_plot_t& first_pending() const { return pending_.front(); }

 private:
  std::int64_t wait_us_, max_gap_us_;
  LocalLevelFrame frame_R_;
  PrlBiasEstimator est_;
  NavBuffer nav_;
  std::deque<prl_plot_t> pending_;
};

}  // namespace rnav
