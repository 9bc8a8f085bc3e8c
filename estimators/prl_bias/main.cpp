// Process "prl_bias": LCM wiring only; the estimator is PrlBiasEstimator. With --free it runs
// without the lock-step clock (PrlBiasFreeNode), driven by the messages' own time stamps.
#include "free_main.hpp"
#include "node_main.hpp"
#include "prl_bias_free_node.hpp"
#include "prl_bias_node.hpp"

#include <cstring>

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--free") == 0)
      return rnav::run_free_main<rnav::Scenario>(
          argc, argv, "rnav_prl_bias",
          [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::FreeArgs& a) -> std::unique_ptr<rnav::FreeNode> {
            rnav::PrlBiasFreeOptions o;
            for (std::size_t k = 0; k + 1 < a.extra.size(); k += 2) {
              if (a.extra[k] == "--nav-lateness-s") o.nav_lateness_s = rnav::parse_number(a.extra[k], a.extra[k + 1], 0, 3600);
              else throw rnav::ConfigError("unknown option " + a.extra[k]);
            }
            std::cerr << "rnav_prl_bias: nav_lateness_s " << o.nav_lateness_s << "\n";
            return std::make_unique<rnav::PrlBiasFreeNode>(bus, sc, o);
          });
  return rnav::run_node_main<rnav::Scenario>(argc, argv, "prl_bias",
                             [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
                               return std::make_unique<rnav::PrlBiasNode>(bus, sc);
                             });
}
