// The lock-step nodes of a recorded scene run (kind "scene"): the truth it replays and its
// sensors, each a process of its own over LCM (scripts/run) or one of the nodes of the
// in-process ensemble.
//   scene_truth           the observer's recorded track (SCENE_OBSERVER) and each target's
//                         reference track (SCENE_TARGETS), every recorded sample in its window;
//   scene_sensor@SENSOR   one sensor's detections and empty scans (SCENE_DETECTIONS_<SENSOR>):
//                         the realization's detections of scene_sim.hpp's simulate() on a scene
//                         holding this sensor only (its random streams are its own: the same
//                         detections as the whole scene's simulation), each in the window of its
//                         scan's time stamp.
// Times: SceneTime (recorded_scene.hpp) maps the recording's times to the run's utimes.
#pragma once

#include "common/node/lockstep_node.hpp"
#include "sim/scene/recorded_scene.hpp"
#include "sim/scene/scene_errors.hpp"
#include "sim/scene/scene_sim.hpp"

#include <string>
#include <vector>

namespace rnav::scene {

/// The node name of a sensor's process: "scene_sensor@" + sensor (scripts/run starts
/// rnav_scene_sensor --instance SENSOR for it).
std::string sensor_node_name(const std::string& sensor);

class SceneTruthNode : public LockstepNode {
 public:
  /// @param peer_timeout_s [s wall] runner.peer_timeout_s
  SceneTruthNode(Bus& bus, const RecordedScene& scene, SceneTime time, double peer_timeout_s);

 protected:
  void reset(const sim_window_t&) override;
  int process(const sim_window_t& w) override;

 private:
  const RecordedScene& scene_;
  SceneTime time_;
  // the first sample not yet published: windows come in order within an attempt (lockstep_node.hpp)
  std::size_t next_observer_ = 0;
  std::vector<std::size_t> next_target_;  // per target, in the scene's (name) order
};

class SceneSensorNode : public LockstepNode {
 public:
  /// @param scene  the whole scene; the node keeps its sensor `sensor` only (std::invalid_argument
  ///               if the scene has no such sensor)
  SceneSensorNode(Bus& bus, const RecordedScene& scene, const std::string& sensor, SceneErrors errors, SceneTime time,
                  double peer_timeout_s);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  RecordedScene scene_;  // the scene with this sensor only
  SceneErrors errors_;
  SceneTime time_;
  std::string channel_;
  std::vector<SceneDetection> det_;  // the realization's, in time order
  std::size_t next_ = 0;             // the first not yet published
};

}  // namespace rnav::scene
