// Process "snsins" (a composition root): LCM wiring only; the model is SnsinsErrorModel.
#include "common/node/node_main.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "sim/snsins/snsins_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_snsins", "snsins",
                        "The navigation solution the ground receives (SNS/INS error model, link rate and latency, "
                        "drop-outs), from TRUTH_AIRCRAFT, published on NAV_SOLUTION (on NAV_SOLUTION_TX when datalink.enabled: "
                        "rnav_datalink then passes on what survives the link).",
                        false},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::SnsinsNode>(bus, sc.snsins, sc.site(), sc.datalink.enabled);
      });
}
