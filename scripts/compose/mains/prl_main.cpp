// Process "prl" (a composition root): LCM wiring only; the model is PrlErrorModel.
#include "common/node/node_main.hpp"
#include "sim/prl/prl_node.hpp"
#include "scripts/compose/scenario/scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_prl", "prl",
                        "The landing radar's plots (slant range, course and glide angle) with systematic and "
                        "fluctuation errors and any prl_effects.*, from TRUTH_AIRCRAFT, published on PRL_APOI; "
                        "the injected errors on TRUTH_PRL_ERROR.",
                        false},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::PrlNode>(bus, sc.prl, sc.prl_effects, sc.site());
      });
}
