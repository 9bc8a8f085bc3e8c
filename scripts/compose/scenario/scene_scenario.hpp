// The recorded-scene scenario (kind "scene"): a recording (the multi-sensor folder format)
// replayed as a simulation, every sensor a process of its own (scene_nodes.hpp), its errors
// nominal or a diagnosis report's (the same scene and errors as build/bin/rnav_scene simulate:
// scripts/compose/scene). Strict parsing as in scenario.hpp. load() reads the recording and
// builds the scene once; every process of a run builds the same (deterministic).
#pragma once

#include "sim/scene/recorded_scene.hpp"
#include "common/node/runner_options.hpp"
#include "sim/scene/scene_errors.hpp"
#include "loggers/scene_logger_options.hpp"
#include "loggers/scene_run_stats.hpp"

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace rnav {

struct MultiSensorData;

/// Section "scene": the recording and its error model.
struct SceneOptions {
  /// The recording folder (observer.csv, detections.csv, truth.csv; rnav_import_autoferry
  /// writes one). A relative path in the file is relative to the file's directory, one given by
  /// --set to the working directory. Required.
  std::string recording;
  /// A multi-sensor diagnosis report (rnav_diagnose multi --json): its named effects and each
  /// channel's identified noise become the sensors' errors; "" for the nominal model (white
  /// noise at sigma_bearing_deg, sigma_range_m). Relative paths as for recording.
  std::string effects_report;
  std::string name;                 ///< the recording's name (a pooled report's recording scope); "" its folder's name
  std::string clutter = "replay";   ///< "replay": the recording's clutter in its own scans; "draw": Poisson per scan from its returns
  /// With a report, each channel's noise: "simulated" (the report's drawn noise, slow wander
  /// included) or "identified" (its identified noise findings alone)
  std::string noise = "simulated";
  double sigma_bearing_deg = 0.5;   ///< [deg] nominal bearing noise (with a report: the report's), (0, 90]
  double sigma_range_m = 1.0;       ///< [m] nominal range noise (with a report: the report's), (0, 1e5]
  double gate_bearing_deg = 3;      ///< [deg] association gate of bearings (coverage, detection probability, clutter), (0, 45]
  double gate_position_m = 20;      ///< [m] association gate of range sensors, (0, 1e5]
  double reference_max_gap_s = 2;   ///< [s] a reference is interpolated only across gaps this short, (0, 1e5]
  /// Seed of the simulation that calibrates the detection probabilities (scene_from_recording.hpp),
  /// [0, 2^53]; rnav_scene simulate uses its --seed for it.
  std::int64_t calibration_seed = 1;
};

/// What load() builds from the recording: the scene, its errors and its time base.
struct SceneSetup {
  std::shared_ptr<const MultiSensorData> data;  ///< the recording as read
  scene::RecordedScene scene;
  scene::SceneErrors errors;
  scene::SceneTime time;
  std::vector<std::string> sensors, targets;
};

struct SceneScenario {
  /// [s] the clock's grid for a scene: runner.window_s is a multiple of it (scripts/run
  /// --realtime uses one step per window).
  static constexpr double kStepS = 0.1;

  std::string name = "scene";
  SceneOptions scene;
  SceneLoggerOptions logger;
  RunnerOptions runner;
  std::shared_ptr<const SceneSetup> setup;  ///< set by load()

  /// Load and validate a scenario file with "a.b=value" overrides applied first, read its
  /// recording and build the scene. Throws ConfigError naming the key or the file.
  static SceneScenario load(const std::string& file, const std::vector<std::string>& overrides = {});
  /// Parse from an already-loaded JSON document (no recording read).
  static SceneScenario from_json(const nlohmann::json& doc);
  void print(std::ostream& os) const;
  std::string json_text() const;
  /// [s] the scene's length (recorded_scene.hpp); needs load().
  double duration_s() const;
  /// scene_truth, scene_sensor@SENSOR per sensor (scene order), scene_logger; needs load().
  std::vector<std::string> node_names() const;
};

/// A realization the scene logger assembled, written as a recording folder `dir` (created; the
/// format of MultiSensorData::write_folder, the recording's hull sizes as targets.csv): what
/// build/bin/rnav_scene simulate writes for the same seed and realization, byte for byte.
void write_scene_recording(const SceneSetup& setup, const SceneRealization& r, const std::string& dir);

}  // namespace rnav
