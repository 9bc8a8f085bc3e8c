// What the azimuth-only statistics read of a UAV scenario: their own options (logger) and the
// models they judge the estimators against: the orbit (uav), the navigation's and the sensor's
// accuracy (uav_nav, sensor) and the estimators' priors (tma), with the shared runner.
#pragma once

#include "sim/uav/observer_options.hpp"
#include "common/node/runner_options.hpp"
#include "sim/uav/sensor_options.hpp"
#include "common/physics/sim_time.hpp"
#include "estimators/uav_tma/tma_options.hpp"
#include "loggers/uav_logger_options.hpp"

#include <cstdint>

namespace rnav {

struct UavStatsSetup {
  UavLoggerOptions logger;  ///< eval_time_s resolved (not -1)
  ObserverOptions uav;
  ObserverNavOptions uav_nav;
  SensorOptions sensor;
  TmaOptions tma;
  RunnerOptions runner;

  /// [s] the summary's evaluation time.
  double eval_time_s() const { return logger.eval_time_s; }
  /// [s] one orbit: 2 pi R / V.
  double orbit_period_s() const { return rnav::orbit_period_s(uav); }
  /// Sim time [us] -> utime [us since Unix epoch].
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }
};

}  // namespace rnav
