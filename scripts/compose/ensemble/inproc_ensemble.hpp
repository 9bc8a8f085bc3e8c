// The whole landing-approach ensemble in one process: the same nodes and clock as the
// multi-process run, on an InprocBus. Used by the benchmark (multi- vs single-process) and by
// the determinism test (its outputs must equal the multi-process run's byte for byte).
#pragma once

#include "sim/clock/conductor.hpp"
#include "common/node/lockstep_node.hpp"

#include <memory>
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <string>

namespace rnav {

struct InprocResult {
  int exit_code = 0;
  std::string failure;
  int retries = 0;
};

/// The landing run's navigation chain: the node "snsins" and, when sc.datalink.enabled, the
/// node "datalink" after it (writing datalink.csv into out_dir if not empty). Every runner
/// builds its node set with this, so the link is part of every one.
void add_nav_nodes(InprocBus& bus, const Scenario& sc, std::vector<std::unique_ptr<LockstepNode>>& nodes,
                   const std::string& out_dir);

/// The node "uav" of a UAV scenario: its own sections, the object's first position, the context.
std::unique_ptr<LockstepNode> make_uav_node(Bus& bus, const UavScenario& sc);

/// Drive any set of nodes and the clock on one InprocBus until the clock is done.
/// `base`: further clock options (e.g. the scenario to publish on SIM_SCENARIO); its
/// n_realizations, seed and nodes are replaced by n, seed and the nodes' names.
InprocResult run_inproc_nodes(InprocBus& bus, std::vector<std::unique_ptr<LockstepNode>>& nodes,
                              const RunnerOptions& runner, double step_s, double duration_s, int n,
                              std::int64_t seed, const std::vector<std::string>& drops = {},
                              const ConductorOptions& base = {});

/// Run n realizations with `seed` (realizations first ... first+n-1: a shard of a larger
/// ensemble when first > 0); write the logger's files into out_dir (if not empty).
/// `drops` inject deliberate message losses (tests).
InprocResult run_inproc_ensemble(const Scenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir,
                                 const std::vector<std::string>& drops = {}, int first = 0);
/// The same for the azimuth-only (UAV) scenario.
InprocResult run_inproc_ensemble(const UavScenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir,
                                 const std::vector<std::string>& drops = {}, int first = 0);

/// The same for a recorded scene (its truth, one node per sensor, its logger).
InprocResult run_inproc_ensemble(const SceneScenario& sc, int n, std::int64_t seed,
                                 const std::string& out_dir,
                                 const std::vector<std::string>& drops = {}, int first = 0);

}  // namespace rnav
