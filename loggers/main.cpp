// Process "logger": LCM wiring only; the statistics are PrlStats.
#include "node_main.hpp"
#include "prl_logger_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv, "logger",
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs& a) {
        if (a.out_dir.empty()) throw rnav::ConfigError("logger: --out DIR is required");
        return std::make_unique<rnav::PrlLoggerNode>(bus, sc, a.out_dir);
      });
}
