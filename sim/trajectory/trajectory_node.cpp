#include "sim/trajectory/trajectory_node.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>

namespace rnav {

TrajectoryNode::TrajectoryNode(Bus& bus, const TrajectoryOptions& o, const SiteContext& site)
    : LockstepNode(bus, "trajectory", site.runner.peer_timeout_s),
      o_(o),
      site_(site),
      traj_(make_trajectory(o, site)),
      frame_L_(site.landing_frame()) {}

int TrajectoryNode::process(const sim_window_t& w) {
  const std::int64_t step = to_us(o_.step_s);
  const std::int64_t t_end_us = to_us(traj_->duration_s());
  const std::int64_t b = w.utime_begin - site_.runner.epoch_utime, e = w.utime_end - site_.runner.epoch_utime;
  aircraft_truth_batch_t batch;
  for (std::int64_t t = (b + step - 1) / step * step; t < e && t <= t_end_us; t += step) {
    const AircraftKinematics k = traj_->at(t * 1e-6);
    aircraft_state_t s;
    s.utime = site_.utime(t);
    for (int i = 0; i < 3; ++i) {
      s.p_TA_L[i] = k.p_TA_L[i];
      s.v_A_L[i] = k.v_A_L[i];
    }
    const Geodetic g = frame_L_.to_geodetic(k.p_TA_L);
    s.lat_deg = g.lat_deg;
    s.lon_deg = g.lon_deg;
    s.h_m = g.h_m;
    batch.states.push_back(s);
  }
  batch.n = static_cast<int>(batch.states.size());
  publish_batch(ch::kTruth, batch);
  return batch.n;
}

}  // namespace rnav
