// Process "uav" (a composition root): LCM wiring only; the models are ObserverPath and UavNode's error model.
#include "common/node/node_main.hpp"
#include "sim/uav/uav_node.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_uav", "uav",
                        "The UAV: its true path, its navigation solution (UAV_NAV) and the passive sensor's "
                        "bearings to the object (UAV_BEARING).",
                        false},
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavNode>(bus, sc.uav, sc.uav_nav, sc.sensor, sc.sensor_effects,
                                               Eigen::Vector2d(sc.target.start_north_m, sc.target.start_east_m),
                                               sc.context());
      });
}
