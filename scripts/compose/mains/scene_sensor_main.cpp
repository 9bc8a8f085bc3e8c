// Process "scene_sensor" (a composition root): LCM wiring only; the node is SceneSensorNode, one
// process per sensor of the scene (--instance SENSOR).
#include "common/io/did_you_mean.hpp"
#include "common/node/node_main.hpp"
#include "sim/scene/scene_nodes.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"

#include <algorithm>

int main(int argc, char** argv) {
  rnav::NodeProgram p{"rnav_scene_sensor", "scene_sensor",
                      "One sensor of a recorded scene (--instance SENSOR): its scans at the recorded times, each target in "
                      "its coverage detected with its measured probability, at its true range and bearing plus the named "
                      "effects and its channel's noise, and the recording's clutter; published on SCENE_DETECTIONS_<SENSOR>."};
  p.instance_of = "the sensor (a sensor name of the recording)";
  return rnav::run_node_main<rnav::SceneScenario>(
      argc, argv, p, [](rnav::Bus& bus, const rnav::SceneScenario& sc, const rnav::NodeArgs& a) {
        const auto& s = sc.setup->sensors;
        if (std::find(s.begin(), s.end(), a.instance) == s.end()) {
          std::string list;
          for (const auto& x : s) list += (list.empty() ? "" : ", ") + x;
          throw rnav::ConfigError("--instance " + a.instance + ": the recording has no such sensor" + rnav::did_you_mean(a.instance, s) +
                                  " (its sensors: " + list + ")");
        }
        return std::make_unique<rnav::scene::SceneSensorNode>(bus, sc.setup->scene, a.instance, sc.setup->errors, sc.setup->time,
                                                              sc.runner.peer_timeout_s);
      });
}
