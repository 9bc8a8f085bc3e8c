// Process "scene_logger" (a composition root): LCM wiring only; the node is SceneLoggerNode and
// the recording folders it writes are write_scene_recording's.
#include "common/node/node_main.hpp"
#include "loggers/scene_logger_node.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::SceneScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_scene_logger", "scene_logger",
                        "A recorded scene run's logger: per sensor, the scans, detections, each target's returns and the "
                        "clutter of every realization (summary.json, summary.txt) and the first logger.recordings "
                        "realizations each as a recording folder realization_NNNNNN/ (scripts/diagnose multi reads it), "
                        "in --out DIR.",
                        true},
      [](rnav::Bus& bus, const rnav::SceneScenario& sc, const rnav::NodeArgs& a) {
        const auto setup = sc.setup;
        return std::make_unique<rnav::SceneLoggerNode>(
            bus, sc.logger, setup->scene.name, setup->sensors, setup->targets, setup->time, sc.runner.peer_timeout_s, sc.json_text(),
            a.out_dir, [setup](const rnav::SceneRealization& r, long, const std::string& dir) { rnav::write_scene_recording(*setup, r, dir); });
      });
}
