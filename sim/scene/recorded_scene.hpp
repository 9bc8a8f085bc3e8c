// A recorded scene as a simulation: the observer's track and each target's reference track
// replayed as the truth, and each sensor as the recording shows it (its scan times, its
// coverage, its detection probability per target, its clutter: replayed where the recording has
// it, or drawn). Plain data: the composition
// root that reads a recording (scripts/compose/scene) measures these from it; scene_sim.hpp
// simulates them with the errors of scene_errors.hpp.
#pragma once

#include "common/physics/frames.hpp"

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav::scene {

/// The bearings and ranges a sensor covers: a target is in coverage when its true bearing lies
/// in the arc [bearing_lo_rad, bearing_lo_rad + bearing_span_rad] (clockwise from north,
/// absolute: the recordings hold no observer heading) and its range in [range_lo_m, range_hi_m].
struct Coverage {
  double bearing_lo_rad = 0;          ///< [rad] the arc's counter-clockwise end, (-pi, pi]
  double bearing_span_rad = 2 * M_PI; ///< [rad] the arc's width, (0, 2 pi]
  double range_lo_m = 0;              ///< [m] nearest range, >= 0
  double range_hi_m = 1e6;            ///< [m] farthest range, > range_lo_m
  bool covers(double bearing_rad, double range_m) const;
};

/// One clutter return as the recording shows it (a detection associated to no target).
struct ClutterSample {
  double range_m = 0;      ///< [m] NaN for a bearing-only sensor
  double bearing_rad = 0;  ///< [rad] clockwise from north
  double t_s = 0;          ///< [s] its scan's time stamp in the recording
};

/// A rotating sensor that stamps each detection at its own illumination time (a ship radar whose
/// stamps hold one detection each; the diagnosis reads it as rotations: rotation_scans.hpp).
/// Its beam points at
///   b(t) = b0 + dir 2 pi (t - t0) / P
/// and a target at bearing beta(t) is lit, in rotation k (t in [t0 + k P, t0 + (k + 1) P)), at
///   t = t0 + k P + P ((dir (beta(t) - b0)) mod 2 pi) / (2 pi).
struct Rotation {
  double period_s = 0;       ///< [s] P, > 0; 0: not rotating (the sensor's scans are its stamps)
  int direction = 1;         ///< dir: +1 clockwise, -1 counter-clockwise
  double t0_s = 0;           ///< [s] t0, the start of rotation 0 (the recording's first detection)
  double b0_rad = 0;         ///< [rad] b0, the beam's bearing at t0, clockwise from north, (-pi, pi]
  bool rotating() const { return period_s > 0; }
  /// The rotations k = 0, 1, ... that start at or before last_s: floor((last_s - t0) / P) + 1
  /// (rotating only).
  long rotations_until(double last_s) const { return static_cast<long>(std::floor((last_s - t0_s) / period_s)) + 1; }
};

/// A sensor of the scene.
struct SceneSensor {
  std::string name;                  ///< [a-z0-9_]+
  bool ranged = false;               ///< measures range as well as bearing
  std::vector<double> scan_times_s;  ///< [s] its scans' time stamps, increasing (each scan is simulated at its stamp)
  double scan_period_s = 0;          ///< [s] median scan interval (scan_time_offset's sweep), > 0
  Coverage coverage;
  std::map<std::string, double> p_detect;  ///< per target: probability of a detection in a scan that covers it, [0, 1]
  /// The recording's clutter, t_s non-decreasing. Replayed (true): each return in its own
  /// scan, where the recording has it (land, piers and buoys stay where they are); else drawn:
  /// a Poisson count per scan at clutter_per_scan, each a return drawn with replacement.
  std::vector<ClutterSample> clutter;
  bool replay_clutter = true;
  double clutter_per_scan = 0;             ///< mean clutter returns per scan (a rotation if rotating; drawn clutter), >= 0
  /// Rotating: each rotation between the first and the last scan time is a scan whose returns
  /// are each stamped at their illumination time, and no empty scans are written.
  Rotation rotation;
};

/// The scene: tracks and sensors.
struct RecordedScene {
  std::string name;                    ///< the recording's name (a pooled report's recording scope)
  std::vector<GeoSample> observer;     ///< the observer's track, t_s increasing
  /// [deg] the observer's heading at observer[i].t_s, clockwise from true north, [0, 360); NaN
  /// where the recording has none. Empty (no heading at all) or the length of observer.
  std::vector<double> observer_heading_deg;
  std::map<std::string, std::vector<GeoSample>> targets;  ///< each target's reference track, t_s increasing
  std::vector<SceneSensor> sensors;
  double reference_max_gap_s = 2;      ///< [s] a reference is interpolated only across gaps this short (as the diagnosis), > 0
  double min_speed_mps = 0.5;          ///< [m/s] a target has a course (hull effects) above this speed, >= 0
  /// Throws std::invalid_argument naming the first fault (empty or unordered track, a sensor
  /// without scans, a probability or rate out of range).
  void check() const;
  /// [s] The scene's start on the recording's time scale: its earliest recorded time (observer,
  /// targets, scans), rounded down to a whole second. Sim time 0 of a run of the scene.
  double start_s() const;
  /// [s] The scene's length from start_s() to its latest recorded time.
  double duration_s() const;
};

/// A recorded time as a run's utime and back: utime = epoch_utime + round((t - start) 1e6).
struct SceneTime {
  double start_s = 0;             ///< [s] RecordedScene::start_s()
  std::int64_t epoch_utime = 0;   ///< [us since Unix epoch] sim time 0 (runner.epoch_utime)
  std::int64_t utime(double t_s) const;
  double t_s(std::int64_t utime) const;
};

}  // namespace rnav::scene
