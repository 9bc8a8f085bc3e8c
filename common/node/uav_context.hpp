// What every process of the azimuth-only (UAV) scenario shares besides its own options: frame
// F's origin, the run's duration and the lock-step runner (whose epoch maps sim time to utime).
// Nodes and libraries take their own options plus this; the composed scenario
// (scripts/compose/scenario/uav_scenario.hpp) makes it.
#pragma once

#include "common/physics/frames.hpp"
#include "common/node/runner_options.hpp"
#include "common/physics/sim_time.hpp"

#include <cstdint>

namespace rnav {

struct UavContext {
  Geodetic origin{63.4389, 10.3950, 0.0};  ///< frame F's origin (default: Trondheim harbour, sea level)
  double duration_s = -1;  ///< [s] sim time (resolved: > 0)
  RunnerOptions runner;

  /// Frame F (x north, z east, y up) at the origin.
  LocalLevelFrame frame() const { return LocalLevelFrame(origin, 0.0); }
  /// Sim time [us] -> utime [us since Unix epoch].
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }
};

}  // namespace rnav
