// Node "uav_tma": wires UAV_NAV and UAV_BEARING to the estimators (make_estimators) and
// publishes every estimator's estimate with covariance at every sensor frame (UAV_TMA).
#pragma once

#include "common/node/lockstep_node.hpp"
#include "estimators/uav_tma/tma_frame.hpp"
#include "common/node/uav_context.hpp"

#include <rnav/bearing_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>

namespace rnav {

/// One window of batches: every nav state's frame (with the bearings at its time) in order;
/// a bearing with no nav state at its time is an error.
void tma_window(std::vector<std::unique_ptr<tma::TmaEstimator>>& est, std::int64_t epoch_utime,
                const observer_batch_t& nav, const bearing_batch_t& bearings, std::vector<tma_estimate_t>& out);

class UavTmaNode : public LockstepNode {
 public:
  UavTmaNode(Bus& bus, const TmaOptions& o, const UavContext& ctx);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  TmaOptions o_;
  UavContext ctx_;
  std::vector<std::unique_ptr<tma::TmaEstimator>> est_;
};

}  // namespace rnav
