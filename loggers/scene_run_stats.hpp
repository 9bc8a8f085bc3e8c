// A recorded scene run's statistics: per sensor, what each realization's simulation produced
// (scans, detections, each target's returns, clutter), its mean and standard deviation over the
// ensemble; summary.json and summary.txt. A realization is what the scene logger received over
// the run's channels (scene_logger_node.hpp).
#pragma once

#include "common/physics/frames.hpp"
#include "sim/scene/scene_sim.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav {

/// One realization as the logger assembled it from SCENE_OBSERVER, SCENE_TARGETS and every
/// sensor's SCENE_DETECTIONS_<SENSOR>, times on the recording's scale.
struct SceneRealization {
  std::vector<GeoSample> observer;
  std::vector<double> observer_heading_deg;  ///< [deg] per observer sample, NaN where unknown
  std::map<std::string, std::vector<GeoSample>> targets;
  /// Per sensor (the scene's sensor order), its detections and empty scans in time order.
  std::vector<std::vector<scene::SceneDetection>> by_sensor;
  /// Every sensor's rows, sensor by sensor (the order of scene::simulate()).
  std::vector<scene::SceneDetection> detections() const;
};

/// Counts per sensor: "scans", "detections" (rows other than empty scans), "clutter", and
/// "target:NAME" per target with a return.
using SceneCounts = std::map<std::string, std::map<std::string, long>>;
SceneCounts scene_counts(const SceneRealization& r);

class SceneRunStats {
 public:
  /// @param recording  the scene's name (summary.json)
  /// @param sensors    the scene's sensors; @param targets its targets (each counted, 0 if never detected)
  SceneRunStats(std::string recording, std::vector<std::string> sensors, std::vector<std::string> targets);
  void add_realization(const SceneRealization& r, long realization);
  long realizations() const { return n_; }
  /// summary.json and summary.txt into dir.
  void write(const std::string& dir, std::int64_t seed) const;
  /// Mean and standard deviation over the realizations of one count (0, 0 if none).
  std::pair<double, double> mean_sd(const std::string& sensor, const std::string& count) const;

 private:
  std::string recording_;
  std::vector<std::string> sensors_, targets_;
  long n_ = 0;
  // per sensor and count: sum and sum of squares over realizations (integers: exact in double up to 2^53)
  std::map<std::string, std::map<std::string, std::pair<double, double>>> sums_;
};

}  // namespace rnav
