// Navigation solutions converted into the radar frame R, and their interpolation to a plot's
// time of validity (cubic Hermite on position and velocity).
#pragma once

#include "common/physics/frames.hpp"

#include <rnav/nav_solution_t.hpp>

#include <Eigen/Dense>

#include <cstdint>
#include <deque>
#include <optional>

namespace rnav {

struct NavInR {
  std::int64_t utime = 0;       ///< [us] validity
  std::int64_t link_utime = 0;  ///< [us] arrival on the ground
  Eigen::Vector3d p_RA_R;       ///< [m] aircraft from radar, frame R
  Eigen::Vector3d v_A_R;        ///< [m/s] velocity, frame R
  double sigma_pos_m = 0;       ///< [m] reported 1 sigma per axis
};

/// Convert a received solution into frame R.
NavInR nav_to_radar_frame(const nav_solution_t& n, const LocalLevelFrame& frame_R);

/// Cubic Hermite interpolation between a and b at utime t (a.utime <= t <= b.utime):
///   p(s) = h00 p_a + h10 dt v_a + h01 p_b + h11 dt v_b, s = (t - t_a)/dt,
///   h00 = 2s^3 - 3s^2 + 1, h10 = s^3 - 2s^2 + s, h01 = -2s^3 + 3s^2, h11 = s^3 - s^2.
Eigen::Vector3d hermite_position(const NavInR& a, const NavInR& b, std::int64_t t);

/// Received solutions in arrival order, with the plot-time decision rule.
class NavBuffer {
 public:
  void add(const NavInR& n);
  void clear() { buf_.clear(); }

  enum class Decision { kWait, kInterpolate, kDropout };
  struct Result {
    Decision decision = Decision::kWait;
    std::optional<NavInR> before, after;  ///< the bracketing solutions for kInterpolate
  };
  /// Decide for a plot at utime t, knowing all arrivals before now_utime:
  ///  - kInterpolate: solutions a (utime <= t) and b (utime >= t) arrived by t + wait_us,
  ///    b.utime - a.utime <= max_gap_us;
  ///  - kDropout: the first solution at or after t arrived by t + wait_us but has no usable
  ///    partner (none before t, or the gap exceeds max_gap_us); or none arrived by t + wait_us
  ///    and now_utime > t + wait_us (the answer can no longer change);
  ///  - kWait: otherwise.
  /// The decision depends only on the solutions' time stamps, never on when this is called.
  Result decide(std::int64_t t, std::int64_t wait_us, std::int64_t max_gap_us,
                std::int64_t now_utime) const;
  /// Forget solutions no plot at or after t can need.
  void prune_before(std::int64_t t, std::int64_t max_gap_us);
  std::size_t size() const { return buf_.size(); }

 private:
  std::deque<NavInR> buf_;
};

}  // namespace rnav
