// Process "uav_tma": LCM wiring only; the estimators are in tma_estimators.hpp.
#include "node_main.hpp"
#include "uav_tma_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv, "uav_tma", [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavTmaNode>(bus, sc);
      });
}
