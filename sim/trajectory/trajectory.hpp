// The aircraft's true motion as the simulation sees it: position and velocity in the landing
// frame L at any time of the run. Two implementations: the analytic ApproachTrajectory (the
// paper's path, the default) and ReplayTrajectory (a recorded approach, e.g. from ADS-B,
// selected by trajectory.replay_csv). Every user (trajectory node, clock, in-process ensemble,
// exporter, tests) obtains it from make_trajectory(), so they cannot disagree on the path or
// the run's duration.
#pragma once

#include "common/node/site_context.hpp"
#include "sim/trajectory/trajectory_options.hpp"

#include <Eigen/Dense>

#include <memory>

namespace rnav {

struct AircraftKinematics {
  Eigen::Vector3d p_TA_L;  ///< [m] aircraft A from threshold T, frame L (x, y, z)
  Eigen::Vector3d v_A_L;   ///< [m/s] velocity, frame L
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// State at sim time t_s [s]; defined on [0, duration_s()] and clamped outside (the state at
  /// the nearest end, velocity included).
  virtual AircraftKinematics at(double t_s) const = 0;
  /// [s] length of the run: the last time at which the aircraft's state is published.
  virtual double duration_s() const = 0;
};

/// The scenario's trajectory: ReplayTrajectory when o.replay_csv is set (the landing frame L
/// comes from site.runway), else ApproachTrajectory. Throws ConfigError for an impossible
/// analytic geometry or a bad replay file (naming file and line).
std::unique_ptr<Trajectory> make_trajectory(const TrajectoryOptions& o, const SiteContext& site);

}  // namespace rnav
