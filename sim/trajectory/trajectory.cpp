#include "sim/trajectory/trajectory.hpp"

#include "sim/trajectory/approach_trajectory.hpp"
#include "sim/trajectory/replay_trajectory.hpp"

namespace rnav {

std::unique_ptr<Trajectory> make_trajectory(const TrajectoryOptions& o, const SiteContext& site) {
  if (!o.replay_csv.empty())
    return std::make_unique<ReplayTrajectory>(o.replay_csv, site.landing_frame(),
                                              o.replay_smoothing_s, o.replay_max_gap_s);
  return std::make_unique<ApproachTrajectory>(o);
}

}  // namespace rnav
