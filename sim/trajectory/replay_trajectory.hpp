// A recorded approach replayed as the aircraft's truth (trajectory.replay_csv).
//
// Input: CSV t_s,lat_deg,lon_deg,h_m (strict: common/csv_table; t_s strictly increasing, no
// step longer than trajectory.replay_max_gap_s). Each row i becomes p_TA_L,i = the geodetic
// point in the landing frame L (LocalLevelFrame at the threshold), at sim time
// t_i = t_s,i - t_s,0 (the first row is sim time 0, the last row ends the run).
//
// Smoothing: ADS-B positions are noisy and, resampled at 5 s, piecewise linear (their velocity
// jumps at every sample), so the replay does not interpolate. At time t it fits, per axis of L,
// a quadratic in tau = t_i - t by weighted least squares to the samples with |tau| < W
// (W = trajectory.replay_smoothing_s) with tricube weights w_i = (1 - |tau_i / W|^3)^3:
//   minimise  sum_i w_i (p_i - c0 - c1 tau_i - c2 tau_i^2)^2,   p(t) = c0,
// and v(t) = dp/dt, the exact derivative of that (window and weights move with t), so the
// published velocity is the derivative of the published position (it equals the fitted slope
// c1 wherever the samples lie on a quadratic). Both are linear in the samples:
// p(t) = sum_i l_i(t) p_i, v(t) = sum_i d_i(t) p_i with d_i = dl_i/dt (weights()).
// Properties: any path quadratic in time (straight legs at constant speed, constant
// acceleration) is reproduced exactly, position and velocity; because the weights and their
// first two derivatives vanish at |tau| = W, p(t) and v(t) are continuous in t (no jumps when
// a sample enters or leaves the window). The price: features shorter than about W are rounded
// (a turn's entry is spread over +-W), and noise of period below ~W is removed.
// Outside [0, duration_s()] the state is clamped to the nearest end (as ApproachTrajectory).
#pragma once

#include "common/physics/frames.hpp"
#include "sim/trajectory/trajectory.hpp"

#include <string>
#include <vector>

namespace rnav {

class ReplayTrajectory : public Trajectory {
 public:
  /// @param csv_file     the recorded approach (see the file comment)
  /// @param frame_L      landing frame L (Scenario::landing_frame())
  /// @param smoothing_s  [s] window half-width W, > 2 x the largest time step of the file
  /// @param max_gap_s    [s] largest allowed time step between rows
  /// Throws ConfigError naming file, line (and column) for unreadable or inconsistent input.
  ReplayTrajectory(const std::string& csv_file, const LocalLevelFrame& frame_L,
                   double smoothing_s, double max_gap_s);

  AircraftKinematics at(double t_s) const override;
  double duration_s() const override { return t_.back(); }

  /// The linear smoother at time t (clamped to [0, duration_s()]): samples first..first+n-1
  /// with position weights l_i and velocity weights d_i = dl_i/dt [1/s].
  struct Weights {
    std::size_t first = 0;
    std::vector<double> l, d;
  };
  Weights weights(double t_s) const;

  std::size_t samples() const { return t_.size(); }
  double sample_time_s(std::size_t i) const { return t_.at(i); }
  const Eigen::Vector3d& sample_p_TA_L(std::size_t i) const { return p_TA_L_.at(i); }

 private:
  std::vector<double> t_;                // [s] sim time of each row
  std::vector<Eigen::Vector3d> p_TA_L_;  // [m] each row in L
  double w_s_;                           // [s] window half-width W
};

}  // namespace rnav
