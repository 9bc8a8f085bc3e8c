// The azimuth-only scenario (docs/method.md section 2): a UAV circling a surface object measures
// bearings to it and estimates its position and velocity. Every process's options composed
// into one file, each section's options (unit, default, range) living with the module they
// configure; strict parsing as in scenario.hpp. Frame F: local level at the origin, x north,
// z east, y up; bearings atan2(east, north), clockwise from north.
#pragma once

#include "sim/uav/observer_options.hpp"
#include "common/node/runner_options.hpp"
#include "sim/uav/sensor_options.hpp"
#include "sim/target/target_options.hpp"
#include "estimators/uav_tma/tma_options.hpp"
#include "common/node/uav_context.hpp"
#include "loggers/uav_logger_options.hpp"
#include "loggers/uav_stats_setup.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace rnav {

struct UavScenario {
  std::string name = "uav";
  Geodetic origin{63.4389, 10.3950, 0.0};  ///< frame F's origin (default: Trondheim harbour, sea level)
  double duration_s = -1;       ///< [s] sim time; -1: two orbit periods (2 * 2 pi R / V)
  TargetOptions target;
  ObserverOptions uav;
  ObserverNavOptions uav_nav;
  SensorOptions sensor;
  SensorEffectsOptions sensor_effects;
  TmaOptions tma;
  UavLoggerOptions logger;
  RunnerOptions runner;

  static UavScenario load(const std::string& file, const std::vector<std::string>& overrides = {});
  static UavScenario from_json(const nlohmann::json& doc);
  void print(std::ostream& os) const;
  /// print()'s text: the effective scenario (what the logger writes as scenario.json).
  std::string json_text() const;

  /// What every node shares: origin, duration, runner.
  UavContext context() const { return UavContext{origin, duration_s, runner}; }
  /// What the UAV logger's statistics read: their own section and the models they judge by.
  UavStatsSetup stats_setup() const { return UavStatsSetup{logger, uav, uav_nav, sensor, tma, runner}; }
  /// Frame F (x north, z east, y up) at the origin.
  LocalLevelFrame frame() const { return LocalLevelFrame(origin, 0.0); }
  /// The UAV's guidance uses the estimator's output (UAV_TMA), i.e. guidance is "los" or "estimate".
  bool closed_loop() const { return rnav::closed_loop(uav); }
  /// [s] one orbit: 2 pi R / V.
  double orbit_period_s() const { return rnav::orbit_period_s(uav); }
  /// [s] the summary's evaluation time.
  double eval_time_s() const { return logger.eval_time_s; }
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }
  /// The lock-step nodes a multi-process run starts, each the process rnav_<name>: target, uav,
  /// uav_tma, uav_logger (scripts/run takes them from `rnav_clock --print-nodes`).
  std::vector<std::string> node_names() const { return {"target", "uav", "uav_tma", "uav_logger"}; }
};

}  // namespace rnav
