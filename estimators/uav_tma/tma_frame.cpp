#include "estimators/uav_tma/tma_frame.hpp"

namespace rnav {

void process_tma_frame(std::vector<std::unique_ptr<tma::TmaEstimator>>& est, std::int64_t epoch_utime,
                       const observer_state_t& o, const std::vector<const bearing_t*>& bearings,
                       std::vector<tma_estimate_t>& out) {
  const double t = (o.utime - epoch_utime) * 1e-6;
  for (auto& e : est) {
    double nis = 0;
    bool updated = false;
    for (const bearing_t* b : bearings) {
      tma::BearingMeas z;
      z.t_s = t;
      z.bearing_rad = b->bearing_rad;
      z.sigma_rad = b->sigma_rad;
      z.p_obs_F = Eigen::Vector2d(o.p_OU_F[0], o.p_OU_F[2]);
      z.sigma_nav_m = o.sigma_pos_m;
      const bool was_init = e->initialized();
      nis += e->process(z);
      updated = updated || was_init;
    }
    if (!e->initialized()) continue;
    if (bearings.empty()) e->predict_to(t);
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
    out.push_back(m);
  }
}

}  // namespace rnav
