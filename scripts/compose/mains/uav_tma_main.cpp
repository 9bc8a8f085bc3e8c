// Process "uav_tma" (a composition root): LCM wiring only; the estimators are in tma_estimators.hpp. With --free it
// runs without the lock-step clock (UavTmaFreeNode), driven by the messages' own time stamps.
#include "common/node/free_main.hpp"
#include "common/node/node_main.hpp"
#include "estimators/uav_tma/uav_tma_free_node.hpp"
#include "estimators/uav_tma/uav_tma_node.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <cstring>
#include <limits>

int main(int argc, char** argv) {
  const rnav::NodeProgram program = {"rnav_uav_tma", "uav_tma",
                          "Azimuth-only estimates of the object's position and velocity with covariance: the "
                          "paper's linearised Kalman filter (ekf), the range-parameterised bank (rpekf), the batch MAP estimator (ml) "
                          "and the particle filter (pf), as tma.estimators lists them.",
                          false, true};
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--free") == 0) {
      rnav::UavTmaFreeOptions o;
      return rnav::run_free_main<rnav::UavScenario>(
          argc, argv, program,
          [&o](rnav::cli::Parser& p) {
            p.value("--bearing-lateness-s", "S", "[s] single samples: how far the bearings may lag the nav states; a frame is processed once a nav state this much later has arrived", "1",
                    [&o](const std::string& v) { o.bearing_lateness_s = rnav::cli::number("--bearing-lateness-s", v, 0, 3600); });
            p.value("--seed", "S", "ensemble seed of the recorded run (an integer): the particle filter's (pf) random stream is that of (seed, realization)", "1",
                    [&o](const std::string& v) {
                      o.seed = rnav::parse_integer("--seed", v, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
                    });
          },
          [&o](rnav::Bus& bus, const rnav::UavScenario& sc) -> std::unique_ptr<rnav::FreeNode> {
            std::cerr << "rnav_uav_tma: bearing_lateness_s " << o.bearing_lateness_s << " seed " << o.seed << "\n";
            return std::make_unique<rnav::UavTmaFreeNode>(bus, sc.tma, sc.context(), o);
          });
    }
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv, program,
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavTmaNode>(bus, sc.tma, sc.context());
      });
}
