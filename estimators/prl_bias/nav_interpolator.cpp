#include "estimators/prl_bias/nav_interpolator.hpp"

#include <stdexcept>

namespace rnav {

NavInR nav_to_radar_frame(const nav_solution_t& n, const LocalLevelFrame& frame_R) {
  NavInR r;
  r.utime = n.utime;
  r.link_utime = n.link_utime;
  const Geodetic g{n.lat_deg, n.lon_deg, n.h_m};
  r.p_RA_R = frame_R.from_geodetic(g);
  r.v_A_R = frame_R.from_ned(g, Eigen::Vector3d(n.v_N[0], n.v_N[1], n.v_N[2]));
  r.sigma_pos_m = n.sigma_pos_m;
  return r;
}

Eigen::Vector3d hermite_position(const NavInR& a, const NavInR& b, std::int64_t t) {
  if (b.utime == a.utime) return a.p_RA_R;
  const double dt = (b.utime - a.utime) * 1e-6;
  const double s = (t - a.utime) * 1e-6 / dt, s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
               h11 = s3 - s2;
  return h00 * a.p_RA_R + h10 * dt * a.v_A_R + h01 * b.p_RA_R + h11 * dt * b.v_A_R;
}

void NavBuffer::add(const NavInR& n) {
  if (!buf_.empty() && n.link_utime < buf_.back().link_utime)
    throw std::runtime_error("NAV_SOLUTION arrivals out of order (link_utime decreased)");
  if (!buf_.empty() && n.utime <= buf_.back().utime)
    throw std::runtime_error("NAV_SOLUTION validity times not increasing");
  buf_.push_back(n);
}

NavBuffer::Result NavBuffer::decide(std::int64_t t, std::int64_t wait_us, std::int64_t max_gap_us,
                                    std::int64_t now_utime) const {
  Result res;
  const std::int64_t deadline = t + wait_us;
  // First solution valid at or after t (validity and arrival are both increasing).
  std::size_t i = 0;
  while (i < buf_.size() && buf_[i].utime < t) ++i;
  const bool have_after = i < buf_.size() && buf_[i].link_utime <= deadline;
  if (have_after) {
    const NavInR& b = buf_[i];
    const NavInR* a = b.utime == t ? &b : (i > 0 ? &buf_[i - 1] : nullptr);
    if (a && b.utime - a->utime <= max_gap_us) {
      res.decision = Decision::kInterpolate;
      res.before = *a;
      res.after = b;
    } else {
      res.decision = Decision::kDropout;
    }
    return res;
  }
  // Arrivals before now_utime are all known: the answer is final once the deadline has passed.
  res.decision = now_utime > deadline ? Decision::kDropout : Decision::kWait;
  return res;
}

void NavBuffer::prune_before(std::int64_t t, std::int64_t max_gap_us) {
  // keep the last solution before t - max_gap and everything after
  while (buf_.size() > 1 && buf_[1].utime <= t - max_gap_us) buf_.pop_front();
}

}  // namespace rnav
