#include "sim/scene/scene_nodes.hpp"

#include <rnav/scene_detection_batch_t.hpp>
#include <rnav/scene_observer_batch_t.hpp>
#include <rnav/scene_target_batch_t.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace rnav::scene {

std::string sensor_node_name(const std::string& sensor) { return "scene_sensor@" + sensor; }

SceneTruthNode::SceneTruthNode(Bus& bus, const RecordedScene& scene, SceneTime time, double peer_timeout_s)
    : LockstepNode(bus, "scene_truth", peer_timeout_s), scene_(scene), time_(time) {}

void SceneTruthNode::reset(const sim_window_t&) {
  next_observer_ = 0;
  next_target_.assign(scene_.targets.size(), 0);
}

int SceneTruthNode::process(const sim_window_t& w) {
  // every sample with utime < utime_end not yet published; one before the window would be a
  // window skipped (an invariant of the protocol)
  const auto take = [&](double t_s, const std::string& what) {
    const std::int64_t u = time_.utime(t_s);
    if (u >= w.utime_end) return false;
    if (u < w.utime_begin) throw std::logic_error(name() + ": a sample of " + what + " at utime " + std::to_string(u) + " precedes window " + std::to_string(w.window));
    return true;
  };
  scene_observer_batch_t ob;
  for (; next_observer_ < scene_.observer.size() && take(scene_.observer[next_observer_].t_s, "the observer"); ++next_observer_) {
    const std::size_t i = next_observer_;
    const GeoSample& g = scene_.observer[i];
    scene_observer_t s;
    s.utime = time_.utime(g.t_s);
    s.lat_deg = g.g.lat_deg;
    s.lon_deg = g.g.lon_deg;
    s.h_m = g.g.h_m;
    s.heading_deg = scene_.observer_heading_deg.empty() ? NAN : scene_.observer_heading_deg[i];
    ob.states.push_back(s);
  }
  ob.n = static_cast<std::int32_t>(ob.states.size());
  scene_target_batch_t tb;
  std::size_t k = 0;
  for (const auto& [name, track] : scene_.targets) {
    for (std::size_t& i = next_target_[k++]; i < track.size() && take(track[i].t_s, "target " + name); ++i) {
      const GeoSample& g = track[i];
      scene_target_t s;
      s.utime = time_.utime(g.t_s);
      s.target = name;
      s.lat_deg = g.g.lat_deg;
      s.lon_deg = g.g.lon_deg;
      s.h_m = g.g.h_m;
      tb.states.push_back(s);
    }
  }
  // increasing utime, targets in name order at equal utime (the map's order, kept by a stable sort)
  std::stable_sort(tb.states.begin(), tb.states.end(), [](const scene_target_t& a, const scene_target_t& b) { return a.utime < b.utime; });
  tb.n = static_cast<std::int32_t>(tb.states.size());
  publish_batch(ch::kSceneObserver, ob);
  publish_batch(ch::kSceneTargets, tb);
  return ob.n + tb.n;
}

namespace {
RecordedScene only_sensor(const RecordedScene& scene, const std::string& sensor) {
  RecordedScene s = scene;
  s.sensors.clear();
  for (const auto& x : scene.sensors)
    if (x.name == sensor) s.sensors.push_back(x);
  if (s.sensors.empty()) throw std::invalid_argument("scene " + scene.name + " has no sensor '" + sensor + "'");
  return s;
}
}  // namespace

SceneSensorNode::SceneSensorNode(Bus& bus, const RecordedScene& scene, const std::string& sensor, SceneErrors errors, SceneTime time,
                                 double peer_timeout_s)
    : LockstepNode(bus, sensor_node_name(sensor), peer_timeout_s),
      scene_(only_sensor(scene, sensor)),
      errors_(std::move(errors)),
      time_(time),
      channel_(ch::scene_detections(sensor)) {}

void SceneSensorNode::reset(const sim_window_t& w) {
  det_ = simulate(scene_, errors_, static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization));
  next_ = 0;
}

int SceneSensorNode::process(const sim_window_t& w) {
  scene_detection_batch_t b;
  for (; next_ < det_.size(); ++next_) {
    const SceneDetection& d = det_[next_];
    const std::int64_t u = time_.utime(d.t_s);
    if (u >= w.utime_end) break;
    // invariant: simulate() gives a sensor's detections in time order and every window follows the last
    if (u < w.utime_begin)
      throw std::logic_error(name() + ": a detection at utime " + std::to_string(u) + " precedes window " + std::to_string(w.window));
    scene_detection_t m;
    m.utime = u;
    m.sensor = d.sensor;
    m.range_m = d.range_m;
    m.bearing_rad = d.bearing_rad;
    m.target = d.target;
    b.detections.push_back(std::move(m));
  }
  if (w.last_window && next_ < det_.size())
    throw std::logic_error(name() + ": " + std::to_string(det_.size() - next_) + " detection(s) after the realization's last window");
  b.n = static_cast<std::int32_t>(b.detections.size());
  publish_batch(channel_, b);
  return b.n;
}

}  // namespace rnav::scene
