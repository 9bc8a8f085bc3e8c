#include "scripts/compose/ensemble/inproc_ensemble.hpp"

#include "loggers/scene_logger_node.hpp"
#include "sim/scene/scene_nodes.hpp"

#include "sim/trajectory/trajectory.hpp"
#include "sim/datalink/datalink_node.hpp"
#include "estimators/prl_bias/prl_bias_node.hpp"
#include "loggers/prl_logger_node.hpp"
#include "sim/prl/prl_node.hpp"
#include "sim/snsins/snsins_node.hpp"
#include "sim/trajectory/trajectory_node.hpp"
#include "sim/target/target_node.hpp"
#include "loggers/uav_logger_node.hpp"
#include "sim/uav/uav_node.hpp"
#include "estimators/uav_tma/uav_tma_node.hpp"

#include <memory>

namespace rnav {

void add_nav_nodes(InprocBus& bus, const Scenario& sc, std::vector<std::unique_ptr<LockstepNode>>& nodes,
                   const std::string& out_dir) {
  nodes.push_back(std::make_unique<SnsinsNode>(bus, sc.snsins, sc.site(), sc.datalink.enabled));
  if (sc.datalink.enabled) nodes.push_back(std::make_unique<DatalinkNode>(bus, sc.datalink, sc.site(), out_dir));
}

std::unique_ptr<LockstepNode> make_uav_node(Bus& bus, const UavScenario& sc) {
  return std::make_unique<UavNode>(bus, sc.uav, sc.uav_nav, sc.sensor, sc.sensor_effects,
                                   Eigen::Vector2d(sc.target.start_north_m, sc.target.start_east_m), sc.context());
}

// Drive nodes and clock on one InprocBus until the clock is done.
InprocResult run_inproc_nodes(InprocBus& bus, std::vector<std::unique_ptr<LockstepNode>>& nodes,
                   const RunnerOptions& runner, double step_s, double duration_s, int n,
                   std::int64_t seed, const std::vector<std::string>& drops,
                   const ConductorOptions& base) {
  ConductorOptions o = base;
  o.nodes.clear();
  o.n_realizations = n;
  o.seed = seed;
  for (const auto& node : nodes) {
    o.nodes.push_back(node->name());
    node->set_clock_watchdog(false);
    node->set_wire(parse_wire(runner.wire));
    for (const auto& d : drops) node->add_drop(DropSpec::parse(d));
  }
  Conductor c(bus, runner, step_s, o, duration_s);
  // Wall time stands still in one process: no timeouts; a lost batch shows as a stall, which
  // the loop below then times out deliberately (fault-injection tests).
  double now = 0;
  for (int guard = 0; !c.done() && guard < 1000; ++guard) {
    for (auto& node : nodes) node->poll(now);
    bus.run_until_idle();
    c.poll(now);
    bus.run_until_idle();
    if (!c.done() && guard > 0) now += 1e6;  // nothing moved without time: let timeouts fire
  }
  InprocResult r;
  r.exit_code = c.done() ? c.exit_code() : 5;
  r.failure = c.done() ? c.failure() : "in-process ensemble did not finish";
  r.retries = static_cast<int>(c.retries().size());
  return r;
}

InprocResult run_inproc_ensemble(const Scenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir, const std::vector<std::string>& drops, int first) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc.trajectory, sc.site()));
  add_nav_nodes(bus, sc, nodes, out_dir);
  nodes.push_back(std::make_unique<PrlNode>(bus, sc.prl, sc.prl_effects, sc.site()));
  nodes.push_back(std::make_unique<PrlBiasNode>(bus, sc.prl_bias, sc.site()));
  nodes.push_back(std::make_unique<PrlLoggerNode>(bus, sc.logger, sc.site(), sc.json_text(), out_dir));
  ConductorOptions shard;
  shard.first_realization = first;
  return run_inproc_nodes(bus, nodes, sc.runner, sc.trajectory.step_s, make_trajectory(sc.trajectory, sc.site())->duration_s(), n, seed, drops, shard);
}

InprocResult run_inproc_ensemble(const UavScenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir, const std::vector<std::string>& drops, int first) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TargetNode>(bus, sc.target, sc.sensor.period_s, sc.context()));
  nodes.push_back(make_uav_node(bus, sc));
  nodes.push_back(std::make_unique<UavTmaNode>(bus, sc.tma, sc.context()));
  nodes.push_back(std::make_unique<UavLoggerNode>(bus, sc.stats_setup(), sc.json_text(), out_dir));
  ConductorOptions shard;
  shard.first_realization = first;
  return run_inproc_nodes(bus, nodes, sc.runner, sc.sensor.period_s, sc.duration_s, n, seed, drops, shard);
}

InprocResult run_inproc_ensemble(const SceneScenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir, const std::vector<std::string>& drops, int first) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  const auto setup = sc.setup;
  const double timeout = sc.runner.peer_timeout_s;
  nodes.push_back(std::make_unique<scene::SceneTruthNode>(bus, setup->scene, setup->time, timeout));
  for (const auto& s : setup->sensors)
    nodes.push_back(std::make_unique<scene::SceneSensorNode>(bus, setup->scene, s, setup->errors, setup->time, timeout));
  nodes.push_back(std::make_unique<SceneLoggerNode>(
      bus, sc.logger, setup->scene.name, setup->sensors, setup->targets, setup->time, timeout, sc.json_text(), out_dir,
      [setup](const SceneRealization& r, long, const std::string& dir) { write_scene_recording(*setup, r, dir); }));
  ConductorOptions shard;
  shard.first_realization = first;
  return run_inproc_nodes(bus, nodes, sc.runner, SceneScenario::kStepS, sc.duration_s(), n, seed, drops, shard);
}

}  // namespace rnav
