// Node "prl_bias": wires PRL_APOI and NAV_SOLUTION to PrlBiasEstimator and publishes
// PRL_BIAS and PRL_TOI. A plot waits for the nav solution after it (NavBuffer::decide), so a
// window's output batches hold the plots decided in that window, in plot order.
#pragma once

#include "lockstep_node.hpp"
#include "prl_bias_estimator.hpp"

#include <deque>

namespace rnav {

class PrlBiasNode : public LockstepNode {
 public:
  PrlBiasNode(Bus& bus, const Scenario& sc);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  Scenario sc_;
  LocalLevelFrame frame_R_;
  PrlBiasEstimator est_;
  NavBuffer nav_;
  std::deque<prl_plot_t> pending_;
};

}  // namespace rnav
