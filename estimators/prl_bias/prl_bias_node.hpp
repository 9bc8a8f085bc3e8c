// Node "prl_bias": wires PRL_APOI and NAV_SOLUTION to PrlBiasEstimator and publishes
// PRL_BIAS and PRL_TOI. A plot waits for the nav solution after it (PrlBiasStream), so a
// window's output batches hold the plots decided in that window, in plot order.
#pragma once

#include "common/node/lockstep_node.hpp"
#include "estimators/prl_bias/prl_bias_stream.hpp"

namespace rnav {

class PrlBiasNode : public LockstepNode {
 public:
  PrlBiasNode(Bus& bus, const PrlBiasOptions& o, const SiteContext& site);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  PrlBiasStream stream_;
  std::vector<PrlBiasEstimator::Output> out_;
};

}  // namespace rnav
