// Association of multi-sensor detections to the targets' reference tracks (truth), and the
// geometry every diagnosis column needs.
//
// Frame: local level at the first observer sample, 2-D (north, east) [m]; each associated
// detection's vectors (d, v_rel, v_target, u_course) are turned into the observer's own local
// orientation at its time (bearings are measured from the local north, which turns by
// dlon sin(lat) as the observer moves: 0.2 deg after 20 km east at 63 deg N). Per scan (one sensor,
// one t_s) and target with a reference position p_T(t) (linear interpolation, no gap longer than
// AssociationOptions::reference_max_gap_s; a reference without heights taken at the frame's level):
// predicted relative position d = p_T - p_O; the detection nearest to it is the target's if
// within the gate (range sensors: distance between the detection's position and p_T; bearing-only
// sensors: bearing difference). A scan where two targets' predictions are within one gate of
// each other is ambiguous for both and left out; a detection claimed by two targets goes to the
// nearer. Clutter (detections of nothing) and missed detections are normal.
#pragma once

#include "multi_sensor_data.hpp"

#include <Eigen/Dense>

#include <map>
#include <string>
#include <vector>

namespace rnav {

struct AssociationOptions {
  double gate_bearing_deg = 3;    ///< [deg] gate of bearing-only sensors, (0, 45]
  double gate_position_m = 20;    ///< [m] gate of range sensors, > 0
  double velocity_half_span_s = 1;///< [s] half-span of the central differences for velocities, > 0
  double min_speed_mps = 0.5;     ///< [m/s] a target's course (for hull offsets) is defined above this speed
  /// [s] a reference track is interpolated (linearly) only between samples at most this far
  /// apart; a detection inside a longer gap is not associated, > 0. 2 s suits a GNSS reference
  /// at 1 Hz or faster; an AIS reference (a report every 2-10 s, 3 min at anchor) needs 10 s or more.
  double reference_max_gap_s = 2;
};

/// One detection associated to a target, with its reference geometry.
struct AssociatedDetection {
  double t_s = 0;
  std::string sensor, target;
  bool has_range = false;
  double bearing_rad = 0;          ///< measured bearing, clockwise from north
  double range_m = 0;              ///< measured range (has_range)
  Eigen::Vector2d d;               ///< [m] reference target position minus observer (local north, east at the observer)
  Eigen::Vector2d v_rel;           ///< [m/s] its rate (target velocity minus observer velocity)
  Eigen::Vector2d v_target;        ///< [m/s] target velocity from its reference track
  Eigen::Vector2d u_course;        ///< unit vector along the target's course; zero below min_speed
  double bearing_pred() const { return std::atan2(d.y(), d.x()); }
  double range_pred() const { return d.norm(); }
  /// d bearing / d d [rad/m] and d range / d d [1], as rows (north, east).
  Eigen::RowVector2d dbearing() const { return Eigen::RowVector2d(-d.y(), d.x()) / d.squaredNorm(); }
  Eigen::RowVector2d drange() const { return Eigen::RowVector2d(d.x(), d.y()) / d.norm(); }
};

struct SensorAssociation {
  int scans = 0, detections = 0, ambiguous_scans = 0;
  std::map<std::string, int> associated, missed;  ///< per target
};

/// Associate every scan; stats per sensor. Throws ConfigError without truth.
std::vector<AssociatedDetection> associate(const MultiSensorData& data, const AssociationOptions& o,
                                           std::map<std::string, SensorAssociation>& stats);

}  // namespace rnav
