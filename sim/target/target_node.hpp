// Node "target": publishes the object's true state (TRUTH_TARGET) on the sensor's frame grid.
#pragma once

#include "common/node/lockstep_node.hpp"
#include "sim/target/target_motion.hpp"
#include "common/node/uav_context.hpp"

namespace rnav {

class TargetNode : public LockstepNode {
 public:
  /// @param step_s  [s] the truth step (the sensor's frame period, sensor.period_s)
  TargetNode(Bus& bus, const TargetOptions& o, double step_s, const UavContext& ctx);

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t& w) override;

 private:
  double step_s_;
  UavContext ctx_;
  TargetMotion motion_;
  LocalLevelFrame frame_;
};

}  // namespace rnav
