#include "scripts/compose/export/prl_export.hpp"

#include "sim/trajectory/trajectory.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "scripts/compose/export/prl_csv_recorder_node.hpp"
#include "sim/prl/prl_node.hpp"
#include "sim/snsins/snsins_node.hpp"
#include "sim/trajectory/trajectory_node.hpp"

namespace rnav {

int export_prl_flight(const Scenario& sc, std::int64_t seed, int realization,
                      const std::string& out_dir, std::string* failure) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc.trajectory, sc.site()));
  add_nav_nodes(bus, sc, nodes, "");  // snsins, and the data link if enabled
  nodes.push_back(std::make_unique<PrlNode>(bus, sc.prl, sc.prl_effects, sc.site()));
  nodes.push_back(std::make_unique<PrlCsvRecorderNode>(bus, sc, realization, out_dir));
  const auto r = run_inproc_nodes(bus, nodes, sc.runner, sc.trajectory.step_s, make_trajectory(sc.trajectory, sc.site())->duration_s(),
                                  realization + 1, seed);
  if (failure) *failure = r.failure;
  return r.exit_code;
}

}  // namespace rnav
