// Process "prl_bias": LCM wiring only; the estimator is PrlBiasEstimator.
#include "node_main.hpp"
#include "prl_bias_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_prl_bias", "prl_bias",
                        "Estimates the radar's systematic error from the navigation solution (one scalar Kalman "
                        "filter per channel) and compensates the plots: PRL_APOI and NAV_SOLUTION in, PRL_TOI and "
                        "PRL_BIAS out.",
                        false},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::PrlBiasNode>(bus, sc);
      });
}
