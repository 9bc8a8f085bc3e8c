// Process "uav_logger": LCM wiring only; the statistics are UavStats.
#include "node_main.hpp"
#include "uav_logger_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv, "uav_logger",
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs& a) {
        if (a.out_dir.empty()) throw rnav::ConfigError("uav_logger: --out DIR is required");
        return std::make_unique<rnav::UavLoggerNode>(bus, sc, a.out_dir);
      });
}
