// Process "trajectory": LCM wiring only; the model is make_trajectory(scenario): ApproachTrajectory or ReplayTrajectory.
#include "node_main.hpp"
#include "trajectory_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(argc, argv, "trajectory",
                             [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
                               return std::make_unique<rnav::TrajectoryNode>(bus, sc);
                             });
}
