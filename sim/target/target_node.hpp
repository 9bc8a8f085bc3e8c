// Node "target": publishes the object's true state (TRUTH_TARGET) on the sensor's frame grid.
#pragma once

#include "lockstep_node.hpp"
#include "target_motion.hpp"

namespace rnav {

class TargetNode : public LockstepNode {
 public:
  TargetNode(Bus& bus, const UavScenario& sc);

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t& w) override;

 private:
  UavScenario sc_;
  TargetMotion motion_;
  LocalLevelFrame frame_;
};

}  // namespace rnav
