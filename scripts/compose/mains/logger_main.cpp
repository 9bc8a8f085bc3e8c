// Process "logger" (a composition root): LCM wiring only; the statistics are PrlStats.
#include "common/node/node_main.hpp"
#include "loggers/prl_logger_node.hpp"
#include "scripts/compose/scenario/scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_logger", "logger",
                        "The landing-radar ensemble's statistics: Table 2 (table2.json, table2.txt), "
                        "stats_time.csv, stats_range.csv in --out DIR.",
                        true},
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs& a) {
        return std::make_unique<rnav::PrlLoggerNode>(bus, sc.logger, sc.site(), sc.json_text(), a.out_dir);
      });
}
