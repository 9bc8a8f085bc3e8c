// The line of sight from the observer to a target of a recorded scene at one time, and the
// geometry the effect columns need (common/physics/multi_effect_columns.hpp), in the tangent plane at
// the observer's position then (GeographicLib::LocalCartesian; the target taken at the
// observer's height: the multi-sensor picture is 2-D), axes (east, north).
#pragma once

#include "common/physics/frames.hpp"
#include "common/physics/multi_effect_columns.hpp"

#include <vector>

namespace rnav::scene {

/// The linearly interpolated position of track at t (latitude and longitude; height too), false
/// outside its samples or inside a gap longer than max_gap_s.
bool track_at(const std::vector<GeoSample>& track, double t, double max_gap_s, Geodetic& out);

struct LineOfSight {
  double range_m = 0;       ///< [m] horizontal range observer -> target
  double bearing_rad = 0;   ///< [rad] true bearing, clockwise from north, (-pi, pi]
  Eigen::Vector2d d = Eigen::Vector2d::Zero();         ///< [m] (east, north) target from observer
  Eigen::Vector2d v_rel = Eigen::Vector2d::Zero();     ///< [m/s] target minus observer velocity
  Eigen::Vector2d v_target = Eigen::Vector2d::Zero();  ///< [m/s] target velocity
};

/// The line of sight at t, velocities by central differences over +-half_span_s (one-sided at
/// a track's ends); false where either track is undefined at t (target: max_gap_s; observer:
/// no gap limit) or the target is within 1 m of the observer.
bool line_of_sight(const std::vector<GeoSample>& observer, const std::vector<GeoSample>& target, double t, double max_gap_s,
                   LineOfSight& los, double half_span_s = 1.0);

/// The effect columns' geometry of a range (is_range) or bearing observation along los at t;
/// the course is defined above min_speed_mps.
multi_effect::Geometry effect_geometry(const LineOfSight& los, bool is_range, double t, double min_speed_mps);

}  // namespace rnav::scene
