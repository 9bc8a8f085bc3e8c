// Node "scene_logger": joins a recorded scene run's SCENE_OBSERVER, SCENE_TARGETS and every
// sensor's SCENE_DETECTIONS_<SENSOR> into one realization (times back on the recording's scale),
// adds it to SceneRunStats when the clock moves past it, and hands realizations 0 ...
// logger.recordings-1 to the writer the composition root gives (a recording folder each:
// realization_NNNNNN/). On FINISH: summary.json, summary.txt and scenario.json
// (ensemble_logger_node.hpp). A detection on another sensor's channel, or out of its window or
// order, is an error naming the channel.
#pragma once

#include "loggers/ensemble_logger_node.hpp"
#include "sim/scene/recorded_scene.hpp"
#include "loggers/scene_logger_options.hpp"
#include "loggers/scene_run_stats.hpp"

#include <functional>
#include <string>
#include <vector>

namespace rnav {

/// Writes one realization into out_dir (a recording folder of its own).
using SceneRecordingWriter = std::function<void(const SceneRealization&, long realization, const std::string& out_dir)>;

/// The folder of realization k: "realization_" and k in six digits.
std::string scene_realization_folder(long realization);

class SceneLoggerNode : public EnsembleLoggerNode<SceneRunStats, SceneRealization> {
 public:
  /// @param sensors  the scene's sensors, in its order (a channel each)
  /// @param targets  the scene's targets
  /// @param write    writes a realization's recording folder (called for realizations below
  ///                 o.recordings when out_dir is not empty)
  SceneLoggerNode(Bus& bus, const SceneLoggerOptions& o, const std::string& recording, std::vector<std::string> sensors,
                  std::vector<std::string> targets, scene::SceneTime time, double peer_timeout_s, std::string scenario_json,
                  std::string out_dir, SceneRecordingWriter write);

 protected:
  void start_realization(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;
  void committed() override;

 private:
  SceneLoggerOptions o_;
  std::vector<std::string> sensors_;
  scene::SceneTime time_;
  SceneRecordingWriter write_;
};

}  // namespace rnav
