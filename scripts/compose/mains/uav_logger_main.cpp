// Process "uav_logger" (a composition root): LCM wiring only; the statistics are UavStats.
#include "common/node/node_main.hpp"
#include "loggers/uav_logger_node.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_uav_logger", "uav_logger",
                        "The azimuth-only ensemble's statistics: RMSE, PCRB, NEES/NIS with chi-square bands "
                        "(summary.json, summary.txt, uav_stats_time.csv), realizations.csv and one "
                        "realization's track.csv in --out DIR.",
                        true},
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs& a) {
        return std::make_unique<rnav::UavLoggerNode>(bus, sc.stats_setup(), sc.json_text(), a.out_dir);
      });
}
