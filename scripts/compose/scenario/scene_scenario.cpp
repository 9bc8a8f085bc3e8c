#include "scripts/compose/scenario/scene_scenario.hpp"

#include "estimators/diagnosis/multi_sensor_data.hpp"
#include "common/io/options_io.hpp"
#include "scripts/compose/scene/scene_effects_json.hpp"
#include "scripts/compose/scene/scene_from_recording.hpp"
#include "sim/scene/scene_nodes.hpp"
#include "scripts/compose/scenario/scenario_paths.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rnav {

namespace options_io {  // found by read_scenario's ADL

template <class V> void visit(SceneOptions& o, V& v) {
  v.str("recording", o.recording);
  v.str("effects_report", o.effects_report);
  v.str("name", o.name);
  v.choice("clutter", o.clutter, {"replay", "draw"});
  v.choice("noise", o.noise, {"simulated", "identified"});
  v.num("sigma_bearing_deg", o.sigma_bearing_deg, 1e-6, 90);
  v.num("sigma_range_m", o.sigma_range_m, 1e-6, 1e5);
  v.num("gate_bearing_deg", o.gate_bearing_deg, 1e-3, 45);
  v.num("gate_position_m", o.gate_position_m, 1e-3, 1e5);
  v.num("reference_max_gap_s", o.reference_max_gap_s, 1e-3, 1e5);
  v.i64("calibration_seed", o.calibration_seed, 0, 9007199254740992.0);
}

template <class F> void for_each_section(SceneScenario& sc, F&& f) {
  f("scene", sc.scene);
  f("logger", sc.logger);
  f("runner", sc.runner);
}

}  // namespace options_io
using namespace options_io;

SceneScenario SceneScenario::from_json(const nlohmann::json& doc) {
  SceneScenario sc;
  // a window of 10 s keeps each sensor's batch small (a rotating radar's replayed clutter is
  // hundreds of returns per scan); the statistics do not depend on it (no node feeds back)
  sc.runner.window_s = 10;
  read_scenario(doc, "scene", sc, [](Section&) {});
  if (sc.scene.recording.empty()) throw ConfigError("scenario key 'scene.recording' is required: the recording folder to replay");
  if (!(sc.runner.window_s > 0))
    throw ConfigError("scenario key 'runner.window_s' must be > 0 in a scene scenario (a realization as one window "
                      "would put a whole recording's detections into one message)");
  require_multiple(sc.runner.window_s, kStepS, "runner.window_s", "the scene's clock step");
  return sc;
}

SceneScenario SceneScenario::load(const std::string& file, const std::vector<std::string>& overrides) {
  SceneScenario sc = load_scenario<SceneScenario>(file, overrides);
  sc.scene.recording = resolve_scenario_path(sc.scene.recording, "scene.recording", file, overrides);
  sc.scene.effects_report = resolve_scenario_path(sc.scene.effects_report, "scene.effects_report", file, overrides);
  auto setup = std::make_shared<SceneSetup>();
  try {
    setup->data = std::make_shared<const MultiSensorData>(MultiSensorData::read_folder(sc.scene.recording));
  } catch (const ConfigError& e) {
    throw ConfigError(file + ": scenario key 'scene.recording': " + e.what());
  }
  const MultiSensorData& d = *setup->data;
  const std::string rec_name = sc.scene.name.empty() ? recording_folder_name(sc.scene.recording) : sc.scene.name;
  AssociationOptions assoc;
  assoc.gate_bearing_deg = sc.scene.gate_bearing_deg;
  assoc.gate_position_m = sc.scene.gate_position_m;
  assoc.reference_max_gap_s = sc.scene.reference_max_gap_s;
  const double sb = sc.scene.sigma_bearing_deg * M_PI / 180;
  if (sc.scene.effects_report.empty()) {
    setup->errors = nominal_errors(sb, sc.scene.sigma_range_m);
  } else {
    std::ifstream f(sc.scene.effects_report);
    if (!f) throw ConfigError(file + ": scenario key 'scene.effects_report': cannot read " + sc.scene.effects_report);
    nlohmann::json report;
    try {
      report = nlohmann::json::parse(f);
    } catch (const nlohmann::json::exception& e) {
      throw ConfigError(file + ": scenario key 'scene.effects_report': " + sc.scene.effects_report + " is not JSON (" + e.what() + ")");
    }
    setup->errors = errors_from_report(report, sc.scene.effects_report, rec_name, sb, sc.scene.sigma_range_m,
                                       sc.scene.noise == "simulated");
  }
  setup->scene = scene_from_recording(d, rec_name, assoc);
  for (auto& s : setup->scene.sensors) s.replay_clutter = sc.scene.clutter == "replay";
  calibrate_detection(setup->scene, d, setup->errors, assoc, static_cast<std::uint64_t>(sc.scene.calibration_seed));
  setup->time = scene::SceneTime{setup->scene.start_s(), sc.runner.epoch_utime};
  for (const auto& s : setup->scene.sensors) setup->sensors.push_back(s.name);
  for (const auto& [t, _] : setup->scene.targets) setup->targets.push_back(t);
  sc.setup = std::move(setup);
  return sc;
}

void SceneScenario::print(std::ostream& os) const {
  print_scenario(*this, os, [](nlohmann::json& j) { j["kind"] = "scene"; });
}

std::string SceneScenario::json_text() const {
  std::ostringstream os;
  print(os);
  return os.str();
}

double SceneScenario::duration_s() const {
  if (!setup) throw std::logic_error("SceneScenario::duration_s before load()");
  return setup->scene.duration_s();
}

std::vector<std::string> SceneScenario::node_names() const {
  if (!setup) throw std::logic_error("SceneScenario::node_names before load()");
  std::vector<std::string> n{"scene_truth"};
  for (const auto& s : setup->sensors) n.push_back(scene::sensor_node_name(s));
  n.push_back("scene_logger");
  return n;
}

void write_scene_recording(const SceneSetup& setup, const SceneRealization& r, const std::string& dir) {
  MultiSensorData d;
  d.observer = r.observer;
  bool heading = false;
  for (double h : r.observer_heading_deg) heading = heading || !std::isnan(h);
  if (heading) d.observer_heading_deg = r.observer_heading_deg;
  d.truth = r.targets;
  d.hull = setup.data->hull;
  for (const auto& x : r.detections()) d.detections.push_back({x.t_s, x.sensor, x.range_m, x.bearing_rad, NAN});
  d.write_folder(dir);
}

}  // namespace rnav
