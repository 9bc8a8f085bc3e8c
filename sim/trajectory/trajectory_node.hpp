// Node "trajectory": publishes the aircraft's true state (TRUTH_AIRCRAFT) on the truth grid
// t = i * trajectory.step_s, in L and on WGS84.
#pragma once

#include "sim/trajectory/trajectory.hpp"
#include "common/node/lockstep_node.hpp"

#include <memory>

namespace rnav {

class TrajectoryNode : public LockstepNode {
 public:
  TrajectoryNode(Bus& bus, const TrajectoryOptions& o, const SiteContext& site);

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t& w) override;

 private:
  TrajectoryOptions o_;
  SiteContext site_;
  std::unique_ptr<Trajectory> traj_;  // make_trajectory(o, site): analytic or replayed
  LocalLevelFrame frame_L_;
};

}  // namespace rnav
