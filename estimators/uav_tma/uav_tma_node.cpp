#include "uav_tma_node.hpp"

#include <rnav/bearing_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <map>

namespace rnav {

UavTmaNode::UavTmaNode(Bus& bus, const UavScenario& sc)
    : LockstepNode(bus, "uav_tma", sc.runner.peer_timeout_s), sc_(sc) {
  add_input<observer_batch_t>("UAV_NAV");
  add_input<bearing_batch_t>("UAV_BEARING");
}

void UavTmaNode::reset(const sim_window_t&) { est_ = tma::make_estimators(sc_.tma); }

int UavTmaNode::process(const sim_window_t&) {
  const auto& nav = input<observer_batch_t>("UAV_NAV");
  const auto& bearings = input<bearing_batch_t>("UAV_BEARING");
  std::multimap<std::int64_t, const bearing_t*> by_time;
  for (const auto& b : bearings.bearings) by_time.emplace(b.utime, &b);
  tma_batch_t out;
  for (const auto& o : nav.states) {
    const double t = (o.utime - sc_.runner.epoch_utime) * 1e-6;
    const auto range = by_time.equal_range(o.utime);
    for (auto& e : est_) {
      double nis = 0;
      bool updated = false;
      for (auto it = range.first; it != range.second; ++it) {
        tma::BearingMeas z;
        z.t_s = t;
        z.bearing_rad = it->second->bearing_rad;
        z.sigma_rad = it->second->sigma_rad;
        z.p_obs_F = Eigen::Vector2d(o.p_OU_F[0], o.p_OU_F[2]);
        z.sigma_nav_m = o.sigma_pos_m;
        const bool was_init = e->initialized();
        nis += e->process(z);
        updated = updated || was_init;
      }
      if (!e->initialized()) continue;
      if (range.first == range.second) e->predict_to(t);
      const tma::Gaussian g = e->estimate();
      tma_estimate_t m;
      m.utime = o.utime;
      m.estimator = e->name();
      m.updated = updated;
      for (int i = 0; i < 4; ++i) {
        m.x[i] = g.x[i];
        for (int j = 0; j < 4; ++j) m.P[i][j] = g.P(i, j);
      }
      m.nis = nis;
      out.estimates.push_back(m);
    }
  }
  for (const auto& b : bearings.bearings)
    if (std::none_of(nav.states.begin(), nav.states.end(),
                     [&](const observer_state_t& o) { return o.utime == b.utime; }))
      throw std::runtime_error("UAV_BEARING at utime " + std::to_string(b.utime) +
                               " has no UAV_NAV solution at its time");
  out.n = static_cast<int>(out.estimates.size());
  publish_batch("UAV_TMA", out);
  return out.n;
}

}  // namespace rnav
