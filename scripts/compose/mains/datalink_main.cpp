// Process "datalink" (a composition root): LCM wiring only; the model is NavLink (link_budget.hpp), the node DatalinkNode.
#include "sim/datalink/datalink_node.hpp"
#include "common/node/node_main.hpp"
#include "scripts/compose/scenario/scenario.hpp"

#include <iostream>

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_datalink", "datalink",
                        "The navigation data link (scenario section datalink, run when datalink.enabled): reads "
                        "NAV_SOLUTION_TX, publishes on NAV_SOLUTION the solutions that survive a peak-power-limited link "
                        "(each lost with the probability of its slant range to the radar), and writes DIR/datalink.csv "
                        "(messages sent and lost per realization) at the end.",
                        true},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs& a) {
        auto node = std::make_unique<rnav::DatalinkNode>(bus, sc.datalink, sc.site(), a.out_dir);
        std::cerr << "datalink: " << node->link().budget().describe() << "\n";
        return node;
      });
}
