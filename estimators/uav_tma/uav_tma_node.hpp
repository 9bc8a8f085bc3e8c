// Node "uav_tma": wires UAV_NAV and UAV_BEARING to the estimators (make_estimators) and
// publishes every estimator's estimate with covariance at every sensor frame (UAV_TMA).
#pragma once

#include "lockstep_node.hpp"
#include "tma_estimators.hpp"

namespace rnav {

class UavTmaNode : public LockstepNode {
 public:
  UavTmaNode(Bus& bus, const UavScenario& sc);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  UavScenario sc_;
  std::vector<std::unique_ptr<tma::TmaEstimator>> est_;
};

}  // namespace rnav
