// LCM channel names of the simulations.
#pragma once

#include <cctype>
#include <string>

namespace rnav::ch {
inline constexpr const char* kWindow = "SIM_WINDOW";          // rnav::sim_window_t, clock -> all
inline constexpr const char* kAck = "SIM_ACK";                // rnav::node_ack_t, all -> clock
inline constexpr const char* kTruth = "TRUTH_AIRCRAFT";       // rnav::aircraft_truth_batch_t
inline constexpr const char* kNav = "NAV_SOLUTION";           // rnav::nav_batch_t, as the ground receives it
inline constexpr const char* kNavTx = "NAV_SOLUTION_TX";      // rnav::nav_batch_t, as the aircraft sends it (datalink.enabled)
inline constexpr const char* kApoi = "PRL_APOI";              // rnav::prl_plot_batch_t, raw plots
inline constexpr const char* kPrlError = "TRUTH_PRL_ERROR";   // rnav::prl_error_batch_t
inline constexpr const char* kToi = "PRL_TOI";                // rnav::prl_plot_batch_t, compensated
inline constexpr const char* kBias = "PRL_BIAS";              // rnav::prl_bias_batch_t
inline constexpr const char* kScenario = "SIM_SCENARIO";      // rnav::sim_scenario_t, clock -> event logs
// Azimuth-only (UAV) scenario.
inline constexpr const char* kTruthTarget = "TRUTH_TARGET";   // rnav::target_truth_batch_t
inline constexpr const char* kTruthUav = "TRUTH_UAV";         // rnav::observer_batch_t, the UAV's true state
inline constexpr const char* kUavNav = "UAV_NAV";             // rnav::observer_batch_t, its navigation solution
inline constexpr const char* kUavBearing = "UAV_BEARING";     // rnav::bearing_batch_t
inline constexpr const char* kUavTma = "UAV_TMA";             // rnav::tma_batch_t, the estimates
// A recorded scene (scene scenario).
inline constexpr const char* kSceneObserver = "SCENE_OBSERVER";  // rnav::scene_observer_batch_t, the observer's recorded track
inline constexpr const char* kSceneTargets = "SCENE_TARGETS";    // rnav::scene_target_batch_t, the targets' reference tracks
/// rnav::scene_detection_batch_t of one sensor: "SCENE_DETECTIONS_" and its name in capitals.
inline std::string scene_detections(const std::string& sensor) {
  std::string c = "SCENE_DETECTIONS_";
  for (char x : sensor) c += static_cast<char>(std::toupper(static_cast<unsigned char>(x)));
  return c;
}
}  // namespace rnav::ch
