// One simulation of a recorded scene: every scan of every sensor at its recorded time; a target
// in the sensor's coverage is detected with its probability, at its true range and bearing plus
// the effects' columns times their values plus its channel's noise; clutter returns drawn from
// the recording's own (Poisson count per scan, places with replacement); a scan with nothing in
// it is kept as an empty scan (the scan count is the recording's). A rotating sensor that stamps
// each return at its own time (recorded_scene.hpp's Rotation) is simulated by rotations
// instead: each target at the time the beam lights it, no empty scans.
//   y = h(truth(t)) + sum_e c_e(geometry) theta_e + n_channel(t)
// Random streams: one per sensor (detections and clutter), one per channel (noise) and one per
// channel for its target offset (SceneErrors::offsets), each
// seeded by (seed, realization, name) only, so that the same seed gives the same detections
// whatever else the scene holds.
#pragma once

#include "sim/scene/recorded_scene.hpp"
#include "sim/scene/scene_errors.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rnav::scene {

/// A simulated detection.
struct SceneDetection {
  double t_s = 0;           ///< [s] the scan's time stamp
  std::string sensor;
  double range_m = 0;       ///< [m] NaN for a bearing-only sensor or an empty scan
  double bearing_rad = 0;   ///< [rad] clockwise from north, (-pi, pi]; NaN for an empty scan
  std::string target;       ///< the target it is of; "" for clutter and empty scans
};

/// Simulated detections in sensor order, then time order, each scan's target detections (in
/// target name order) before its clutter (a rotating sensor's: in time order alone). Throws std::invalid_argument for an invalid scene or
/// errors.
std::vector<SceneDetection> simulate(const RecordedScene& scene, const SceneErrors& errors, std::uint64_t seed,
                                     std::uint64_t realization);

}  // namespace rnav::scene
