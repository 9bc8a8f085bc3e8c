// Process "target" (a composition root): LCM wiring only; the model is TargetMotion.
#include "common/node/node_main.hpp"
#include "sim/target/target_node.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_target", "target",
                        "The object's true state (constant velocity, scripted manoeuvres target.manoeuvres), "
                        "published on TRUTH_TARGET.",
                        false},
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::TargetNode>(bus, sc.target, sc.sensor.period_s, sc.context());
      });
}
