// A geodetic time series (observer or target positions) in a local level frame F's horizontal
// plane: 2-D vectors (north, east) [m], linearly interpolated in time.
#pragma once

#include "common/physics/frames.hpp"

#include <Eigen/Dense>

#include <vector>

namespace rnav {

class PlaneSeries {
 public:
  /// @param v  samples in time order (kept by reference: must outlive this object)
  /// @param F  frame with x north, z east (LocalLevelFrame with bearing 0)
  /// @param max_gap_s  [s] interpolation is refused across a longer gap between samples, > 0
  PlaneSeries(const std::vector<GeoSample>& v, const LocalLevelFrame& F, double max_gap_s = 2.0);
  /// Position at t_s (north, east) [m]; false outside the span or across a gap.
  bool at(double t_s, Eigen::Vector2d& out) const;
  /// The linear interpolation's lever at t_s: b = (t_s - t_a)(t_b - t_s) [s^2] between the samples
  /// t_a <= t_s <= t_b around it (0 at a sample), and their interval t_b - t_a [s]; false where
  /// at() is false. A track with acceleration a between the samples is off the chord by
  /// a b / 2 [m].
  bool bridge(double t_s, double& b_s2, double& interval_s) const;
  /// RMS per horizontal axis of the track's acceleration [m/s^2] from the second differences of
  /// consecutive samples (both intervals within max_gap_s), 0 with fewer than three such samples.
  /// The samples' own noise adds (sigma sqrt(6) / dt^2 at spacing dt): an upper estimate.
  double accel_rms() const { return accel_rms_; }
  /// Velocity at t_s [m/s], central difference of at() over t_s +- half_span_s; false if either end fails.
  bool velocity(double t_s, double half_span_s, Eigen::Vector2d& out) const;
  double t_first() const;
  double t_last() const;

 private:
  const std::vector<GeoSample>& v_;
  std::vector<Eigen::Vector2d> p_;
  double max_gap_s_;
  double accel_rms_ = 0;
};

}  // namespace rnav
