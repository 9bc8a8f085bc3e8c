// Process "scene_truth" (a composition root): LCM wiring only; the node is SceneTruthNode.
#include "common/node/node_main.hpp"
#include "sim/scene/scene_nodes.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"

int main(int argc, char** argv) {
  return rnav::run_node_main<rnav::SceneScenario>(
      argc, argv,
      rnav::NodeProgram{"rnav_scene_truth", "scene_truth",
                        "A recorded scene's truth: the observer's recorded track (SCENE_OBSERVER) and each target's reference "
                        "track (SCENE_TARGETS), every recorded sample in its window."},
      [](rnav::Bus& bus, const rnav::SceneScenario& sc, const rnav::NodeArgs&) {
        return std::make_unique<rnav::scene::SceneTruthNode>(bus, sc.setup->scene, sc.setup->time, sc.runner.peer_timeout_s);
      });
}
