// Process "prl_bias" (a composition root): LCM wiring only; the estimator is PrlBiasEstimator. With --free it runs
// without the lock-step clock (PrlBiasFreeNode), driven by the messages' own time stamps.
#include "common/node/free_main.hpp"
#include "common/node/node_main.hpp"
#include "estimators/prl_bias/prl_bias_free_node.hpp"
#include "estimators/prl_bias/prl_bias_node.hpp"
#include "scripts/compose/scenario/scenario.hpp"

#include <cstring>

int main(int argc, char** argv) {
  const rnav::NodeProgram program = {"rnav_prl_bias", "prl_bias",
                          "Estimates the radar's systematic error from the navigation solution (one scalar Kalman "
                          "filter per channel) and compensates the plots: PRL_APOI and NAV_SOLUTION in, PRL_TOI and "
                          "PRL_BIAS out.",
                          false, true};
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--free") == 0) {
      rnav::PrlBiasFreeOptions o;
      return rnav::run_free_main<rnav::Scenario>(
          argc, argv, program,
          [&o](rnav::cli::Parser& p) {
            p.value("--nav-lateness-s", "S", "[s] single samples: how far the nav link may lag the radar; a silent link counts as a drop-out once a plot this much later than the wait has arrived", "1",
                    [&o](const std::string& v) { o.nav_lateness_s = rnav::cli::number("--nav-lateness-s", v, 0, 3600); });
          },
          [&o](rnav::Bus& bus, const rnav::Scenario& sc) -> std::unique_ptr<rnav::FreeNode> {
            std::cerr << "rnav_prl_bias: nav_lateness_s " << o.nav_lateness_s << "\n";
            return std::make_unique<rnav::PrlBiasFreeNode>(bus, sc.prl_bias, sc.site(), o);
          });
    }
  return rnav::run_node_main<rnav::Scenario>(
      argc, argv, program,
      [](rnav::Bus& bus, const rnav::Scenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::PrlBiasNode>(bus, sc.prl_bias, sc.site());
      });
}
