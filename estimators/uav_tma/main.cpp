// Process "uav_tma": LCM wiring only; the estimators are in tma_estimators.hpp. With --free it
// runs without the lock-step clock (UavTmaFreeNode), driven by the messages' own time stamps.
#include "free_main.hpp"
#include "node_main.hpp"
#include "uav_tma_free_node.hpp"
#include "uav_tma_node.hpp"

#include <cstring>

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--free") == 0)
      return rnav::run_free_main<rnav::UavScenario>(
          argc, argv, "rnav_uav_tma",
          [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::FreeArgs& a) -> std::unique_ptr<rnav::FreeNode> {
            rnav::UavTmaFreeOptions o;
            for (std::size_t k = 0; k + 1 < a.extra.size(); k += 2) {
              if (a.extra[k] == "--bearing-lateness-s")
                o.bearing_lateness_s = rnav::parse_number(a.extra[k], a.extra[k + 1], 0, 3600);
              else throw rnav::ConfigError("unknown option " + a.extra[k]);
            }
            std::cerr << "rnav_uav_tma: bearing_lateness_s " << o.bearing_lateness_s << "\n";
            return std::make_unique<rnav::UavTmaFreeNode>(bus, sc, o);
          });
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv, "uav_tma", [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavTmaNode>(bus, sc);
      });
}
