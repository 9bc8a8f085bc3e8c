#include "sim/snsins/snsins_node.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>

namespace rnav {

SnsinsNode::SnsinsNode(Bus& bus, const SnsinsOptions& o, const SiteContext& site, bool via_datalink)
    : LockstepNode(bus, "snsins", site.runner.peer_timeout_s),
      o_(o),
      site_(site),
      via_datalink_(via_datalink),
      frame_L_(site.landing_frame()),
      model_(o) {
  add_input<aircraft_truth_batch_t>(ch::kTruth);
}

void SnsinsNode::reset(const sim_window_t& w) {
  rng_.emplace(static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization),
               Stream::kSnsins);
  model_.start(*rng_);
  pending_.clear();
}

bool SnsinsNode::in_dropout(double t_s) const {
  for (const auto& d : o_.dropouts)
    if (t_s >= d.first && t_s < d.second) return true;
  return false;
}

int SnsinsNode::process(const sim_window_t& w) {
  const auto& truth = input<aircraft_truth_batch_t>(ch::kTruth);
  const std::int64_t period = to_us(o_.link_period_s), phase = to_us(o_.link_phase_s);
  const std::int64_t latency = to_us(o_.latency_s);
  for (const auto& s : truth.states) {
    const std::int64_t t = s.utime - site_.runner.epoch_utime;
    if (t < phase || (t - phase) % period != 0) continue;
    model_.step(t * 1e-6, *rng_);  // the error process runs through drop-outs too
    if (in_dropout(t * 1e-6)) continue;
    const Eigen::Vector3d p_L = Eigen::Vector3d(s.p_TA_L[0], s.p_TA_L[1], s.p_TA_L[2]) + model_.dp_L();
    const Eigen::Vector3d v_L = Eigen::Vector3d(s.v_A_L[0], s.v_A_L[1], s.v_A_L[2]) + model_.dv_L();
    const Geodetic g = frame_L_.to_geodetic(p_L);
    const Eigen::Vector3d v_N = frame_L_.to_ned(g, v_L);
    nav_solution_t n;
    n.utime = s.utime;
    n.link_utime = s.utime + latency;
    n.lat_deg = g.lat_deg;
    n.lon_deg = g.lon_deg;
    n.h_m = g.h_m;
    for (int i = 0; i < 3; ++i) n.v_N[i] = v_N[i];
    n.sigma_pos_m = model_.sigma_pos_m();
    pending_.push_back(n);
  }
  nav_batch_t batch;
  while (!pending_.empty() && pending_.front().link_utime < w.utime_end) {
    batch.solutions.push_back(pending_.front());
    pending_.pop_front();
  }
  batch.n = static_cast<int>(batch.solutions.size());
  // With the data link modelled, this is what the aircraft sends; the node "datalink" decides
  // what reaches the ground (NAV_SOLUTION).
  publish_batch(via_datalink_ ? ch::kNavTx : ch::kNav, batch);
  return batch.n;
}

}  // namespace rnav
