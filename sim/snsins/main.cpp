// Process "snsins": LCM wiring only; the model is SnsinsErrorModel.
#include "node_main.hpp"
#include "snsins_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(argc, argv, "snsins",
                             [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
                               return std::make_unique<rnav::SnsinsNode>(bus, sc);
                             });
}
