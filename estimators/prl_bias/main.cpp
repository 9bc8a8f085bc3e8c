// Process "prl_bias": LCM wiring only; the estimator is PrlBiasEstimator.
#include "node_main.hpp"
#include "prl_bias_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(argc, argv, "prl_bias",
                             [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
                               return std::make_unique<rnav::PrlBiasNode>(bus, sc);
                             });
}
