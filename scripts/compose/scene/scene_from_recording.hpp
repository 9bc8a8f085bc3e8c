// A recording (the multi-sensor folder format) as a recorded scene (sim/scene): its tracks
// replayed as the truth, and each sensor as the recording shows it, measured through the
// diagnosis's own association (estimators/diagnosis/multi_association.hpp):
//   scans          the sensor's distinct time stamps (empty scans included);
//   scan period    the median interval between them;
//   coverage       the smallest bearing arc holding every detection of the sensor (its largest
//                  empty gap left out), widened by kCoverageMarginDeg on each side; ranges
//                  between the nearest and farthest of its associated detections' ranges
//                  (bearing-only sensors: their predicted ranges), widened by kCoverageMarginFrac;
//   p_detect       per sensor and target: its associated detections over those of a
//                  simulation of the scene that detects every covered target in every scan
//                  (the same errors, the same association: its coverage, ambiguous scans and
//                  gate losses taken as the recording's), at most 1 (calibrate_detection);
//   clutter        every detection associated to no target, replayed in its own scan (land,
//                  piers, buoys and the other returns stay where and when the recording has
//                  them), except those within two gates of a target the sensor detects (that
//                  target's own returns the association left out: another point of its hull,
//                  a gross error; the simulation makes its returns itself); their mean count
//                  per scan for drawn clutter.
// Limits, stated: the coverage is absolute (the recordings hold no observer heading, so a
// camera's sector does not turn with the ferry), and detections of a target outside its gate
// count as clutter.
#pragma once

#include "estimators/diagnosis/multi_association.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"
#include "sim/scene/recorded_scene.hpp"
#include "sim/scene/scene_sim.hpp"

#include <string>

namespace rnav {

constexpr double kCoverageMarginDeg = 1.0;   ///< [deg] each side of the bearing arc
constexpr double kCoverageMarginFrac = 0.05; ///< of the range interval, each side

/// The scene of recording `data` named `name`, with association options o (the diagnosis's).
/// Throws ConfigError (from the association) for a recording it cannot associate.
scene::RecordedScene scene_from_recording(const MultiSensorData& data, const std::string& name, const AssociationOptions& o);

/// Sets each sensor's p_detect of `scene` (built by scene_from_recording, whose p_detect are
/// the placeholders 1) to the recording's associated detections over those of a simulation
/// with every p_detect 1 and these errors (seed `seed`, a realization of its own), at most 1.
void calibrate_detection(scene::RecordedScene& scene, const MultiSensorData& real, const scene::SceneErrors& errors,
                         const AssociationOptions& o, std::uint64_t seed);

/// A recording's name from its folder: the folder's own name ("a/b/sc5/" -> "sc5").
std::string recording_folder_name(const std::string& dir);

/// The simulated detections as a recording: the scene's observer and truth with `det`, marked
/// simulated (MultiSensorData::simulated: the unit check is not run on it).
MultiSensorData recording_of(const MultiSensorData& real, const std::vector<scene::SceneDetection>& det);

}  // namespace rnav
