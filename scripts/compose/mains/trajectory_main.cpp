// Process "trajectory" (a composition root): LCM wiring only; the model is make_trajectory(scenario): ApproachTrajectory or ReplayTrajectory.
#include "common/node/node_main.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "sim/trajectory/trajectory_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_trajectory", "trajectory",
                        "The aircraft's true path (landing frame L and WGS84) on the truth grid, published on "
                        "TRUTH_AIRCRAFT: the approach of the scenario, or a replayed flight "
                        "(trajectory.replay_csv).",
                        false},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::TrajectoryNode>(bus, sc.trajectory, sc.site());
      });
}
