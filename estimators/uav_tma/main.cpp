// Process "uav_tma": LCM wiring only; the estimators are in tma_estimators.hpp.
#include "node_main.hpp"
#include "uav_tma_node.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::UavScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_uav_tma", "uav_tma",
                        "Azimuth-only estimates of the object's position and velocity with covariance: the "
                        "paper's linearised Kalman filter (ekf) and the range-parameterised bank (rpekf).",
                        false},
      [](rnav::Bus& bus, const rnav::UavScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::UavTmaNode>(bus, sc);
      });
}
