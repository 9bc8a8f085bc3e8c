#include "scripts/compose/export/lcm_log_export.hpp"

#include "sim/trajectory/trajectory.hpp"
#include "common/io/config.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "estimators/prl_bias/prl_bias_node.hpp"
#include "sim/prl/prl_node.hpp"
#include "sim/snsins/snsins_node.hpp"
#include "sim/target/target_node.hpp"
#include "sim/trajectory/trajectory_node.hpp"
#include "sim/uav/uav_node.hpp"
#include "estimators/uav_tma/uav_tma_node.hpp"

#include <lcm/lcm-cpp.hpp>

namespace rnav {

LcmLogTap::LcmLogTap(InprocBus& bus, const std::string& file, std::int64_t first_timestamp_us)
    : bus_(bus), file_(file), log_(std::make_unique<lcm::LogFile>(file, "w")), t_(first_timestamp_us) {
  if (!log_->good()) throw std::runtime_error("cannot open " + file + " for writing");
  bus_.on_publish = [this](const std::string& channel, const void* data, int size) {
    lcm::LogEvent e;
    e.eventnum = 0;  // set by LCM
    e.timestamp = t_++;
    e.channel = channel;
    e.datalen = size;
    e.data = const_cast<void*>(data);
    if (log_->writeEvent(&e) != 0) throw std::runtime_error("cannot write to " + file_);
    ++n_;
  };
}

LcmLogTap::~LcmLogTap() { bus_.on_publish = nullptr; }

int export_lcm_log(const std::string& scenario_file, const std::vector<std::string>& overrides,
                   std::int64_t seed, int n, const std::string& log_file,
                   const std::vector<std::string>& drops, std::string* failure) {
  // The clock's SIM_SCENARIO: the file with the overrides applied (as rnav_clock publishes it).
  nlohmann::json doc = load_json_file(scenario_file);
  for (const auto& ov : overrides) apply_override(doc, ov);
  ConductorOptions base;
  base.scenario_kind = scenario_kind(scenario_file);
  if (base.scenario_kind == "scene")
    throw ConfigError(scenario_file + ": a recorded scene (kind \"scene\") is not exported this way; record its run with "
                      "scripts/run SCENARIO --lcm-log FILE");
  base.scenario_source = scenario_file;
  base.scenario_json = doc.dump();

  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  InprocResult r;
  if (base.scenario_kind == "uav") {
    const UavScenario sc = UavScenario::load(scenario_file, overrides);
    nodes.push_back(std::make_unique<TargetNode>(bus, sc.target, sc.sensor.period_s, sc.context()));
    nodes.push_back(make_uav_node(bus, sc));
    nodes.push_back(std::make_unique<UavTmaNode>(bus, sc.tma, sc.context()));
    LcmLogTap tap(bus, log_file, sc.runner.epoch_utime);
    r = run_inproc_nodes(bus, nodes, sc.runner, sc.sensor.period_s, sc.duration_s, n, seed, drops, base);
  } else {
    const Scenario sc = Scenario::load(scenario_file, overrides);
    nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc.trajectory, sc.site()));
    add_nav_nodes(bus, sc, nodes, "");  // snsins, and the data link if enabled
    nodes.push_back(std::make_unique<PrlNode>(bus, sc.prl, sc.prl_effects, sc.site()));
    nodes.push_back(std::make_unique<PrlBiasNode>(bus, sc.prl_bias, sc.site()));
    LcmLogTap tap(bus, log_file, sc.runner.epoch_utime);
    r = run_inproc_nodes(bus, nodes, sc.runner, sc.trajectory.step_s, make_trajectory(sc.trajectory, sc.site())->duration_s(), n, seed, drops, base);
  }
  if (failure) *failure = r.failure;
  return r.exit_code;
}

}  // namespace rnav
