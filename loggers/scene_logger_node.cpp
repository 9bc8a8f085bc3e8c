#include "loggers/scene_logger_node.hpp"

#include <rnav/scene_detection_batch_t.hpp>
#include <rnav/scene_observer_batch_t.hpp>
#include <rnav/scene_target_batch_t.hpp>

#include <filesystem>
#include <stdexcept>

namespace rnav {

std::string scene_realization_folder(long realization) {
  std::string n = std::to_string(realization);
  if (n.size() < 6) n.insert(0, 6 - n.size(), '0');
  return "realization_" + n;
}

SceneLoggerNode::SceneLoggerNode(Bus& bus, const SceneLoggerOptions& o, const std::string& recording, std::vector<std::string> sensors,
                                 std::vector<std::string> targets, scene::SceneTime time, double peer_timeout_s,
                                 std::string scenario_json, std::string out_dir, SceneRecordingWriter write)
    : EnsembleLoggerNode(bus, "scene_logger", peer_timeout_s, SceneRunStats(recording, sensors, std::move(targets)),
                         std::move(scenario_json), std::move(out_dir)),
      o_(o),
      sensors_(std::move(sensors)),
      time_(time),
      write_(std::move(write)) {
  add_input<scene_observer_batch_t>(ch::kSceneObserver);
  add_input<scene_target_batch_t>(ch::kSceneTargets);
  for (const auto& s : sensors_) add_input<scene_detection_batch_t>(ch::scene_detections(s));
}

void SceneLoggerNode::start_realization(const sim_window_t&) { current_.by_sensor.assign(sensors_.size(), {}); }

int SceneLoggerNode::process(const sim_window_t& w) {
  // every sample's utime in the window, in non-decreasing order (the publishers' contract)
  auto check = [&w](std::int64_t u, std::int64_t& last, const std::string& channel) {
    if (u < w.utime_begin || u >= w.utime_end || u < last)
      throw std::runtime_error("scene_logger: channel " + channel + " holds a sample at utime " + std::to_string(u) +
                               " out of window " + std::to_string(w.window) + " [" + std::to_string(w.utime_begin) + ", " +
                               std::to_string(w.utime_end) + ") or out of order");
    last = u;
  };
  int n = 0;
  std::int64_t last = w.utime_begin;
  for (const auto& s : input<scene_observer_batch_t>(ch::kSceneObserver).states) {
    check(s.utime, last, ch::kSceneObserver);
    current_.observer.push_back({time_.t_s(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
    current_.observer_heading_deg.push_back(s.heading_deg);
    ++n;
  }
  last = w.utime_begin;
  for (const auto& s : input<scene_target_batch_t>(ch::kSceneTargets).states) {
    check(s.utime, last, ch::kSceneTargets);
    current_.targets[s.target].push_back({time_.t_s(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
    ++n;
  }
  for (std::size_t k = 0; k < sensors_.size(); ++k) {
    const std::string channel = ch::scene_detections(sensors_[k]);
    last = w.utime_begin;
    for (const auto& d : input<scene_detection_batch_t>(channel).detections) {
      check(d.utime, last, channel);
      if (d.sensor != sensors_[k])
        throw std::runtime_error("scene_logger: channel " + channel + " carries a detection of sensor '" + d.sensor + "'");
      current_.by_sensor[k].push_back({time_.t_s(d.utime), d.sensor, d.range_m, d.bearing_rad, d.target});
      ++n;
    }
  }
  return n;
}

void SceneLoggerNode::committed() {
  if (out_dir_.empty() || realization_ >= o_.recordings || !write_) return;
  write_(current_, realization_, (std::filesystem::path(out_dir_) / scene_realization_folder(realization_)).string());
}

}  // namespace rnav
