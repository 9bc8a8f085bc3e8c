// Process "prl": LCM wiring only; the model is PrlErrorModel.
#include "node_main.hpp"
#include "prl_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(argc, argv, "prl",
                             [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
                               return std::make_unique<rnav::PrlNode>(bus, sc);
                             });
}
