// Process "uav": LCM wiring only; the models are ObserverPath and UavNode's error model.
#include "node_main.hpp"
#include "uav_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv, "uav", [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavNode>(bus, sc);
      });
}
