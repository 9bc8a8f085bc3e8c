#include "inproc_ensemble.hpp"

#include "approach_trajectory.hpp"
#include "prl_bias_node.hpp"
#include "prl_logger_node.hpp"
#include "prl_node.hpp"
#include "snsins_node.hpp"
#include "trajectory_node.hpp"

#include <memory>

namespace rnav {

InprocResult run_inproc_ensemble(const Scenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir, const std::vector<std::string>& drops) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc));
  nodes.push_back(std::make_unique<SnsinsNode>(bus, sc));
  nodes.push_back(std::make_unique<PrlNode>(bus, sc));
  nodes.push_back(std::make_unique<PrlBiasNode>(bus, sc));
  nodes.push_back(std::make_unique<PrlLoggerNode>(bus, sc, out_dir));
  ConductorOptions o;
  o.n_realizations = n;
  o.seed = seed;
  for (const auto& node : nodes) {
    o.nodes.push_back(node->name());
    for (const auto& d : drops) node->add_drop(DropSpec::parse(d));
  }
  const ApproachTrajectory traj(sc.trajectory);
  Conductor c(bus, sc.runner, sc.trajectory.step_s, o, traj.duration_s());
  // Wall time stands still in one process: no timeouts; a lost batch shows as a stall.
  for (auto& node : nodes) node->poll(0.0);
  bus.run_until_idle();
  c.poll(0.0);  // all HELLOs are in: grant the first window
  bus.run_until_idle();
  c.poll(0.0);
  bus.run_until_idle();
  InprocResult r;
  if (!c.done()) {
    // Something is waiting for a message that will never come (dropped): time out now.
    for (auto& node : nodes) node->poll(1e9);
    bus.run_until_idle();
    c.poll(1e9);
    bus.run_until_idle();
    int guard = 0;
    while (!c.done() && guard++ < 1000) {
      for (auto& node : nodes) node->poll(1e9 + guard);
      bus.run_until_idle();
      c.poll(1e9 + guard);
      bus.run_until_idle();
    }
  }
  r.exit_code = c.done() ? c.exit_code() : 5;
  r.failure = c.done() ? c.failure() : "in-process ensemble did not finish";
  r.retries = static_cast<int>(c.retries().size());
  return r;
}

}  // namespace rnav
