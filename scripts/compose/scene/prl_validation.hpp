// What the landing-radar simulation gets wrong on a flight, measured: a landing flight (the
// flight-test CSV format, prl_flight_data.hpp) replayed as a scene — its navigation track as
// the aircraft's trajectory (trajectory.replay_csv), its radar site, runway and azimuth
// reference as the scenario's, the radar's plot period and phase from its time stamps — and
// simulated N times per model (nominal: the base scenario's radar; extended: the effects of a
// landing-radar diagnosis report, prl_report.hpp). Each simulated flight is written by the
// exporter (rnav_export_prl's recorder) and read back like the real one; the flight and every
// simulation are then measured the same way (scene_validation.hpp's rows):
//   residual     plot minus the polar position of the nav solution interpolated linearly to the
//                plot's time, per channel: range [m], azimuth and elevation [rad];
//   statistics   mean, sd, lag-1 autocorrelation per channel, and the detection rate: plots
//                over the scans of their span at the flight's median interval.
// Pair name "radar:aircraft"; quantities range, azimuth, elevation.
#pragma once

#include "estimators/diagnosis/prl_flight_data.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/scene/scene_validation.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rnav {

/// The statistics of a flight (residuals against its own nav solution).
SceneStats prl_flight_stats(const PrlFlightData& f);

/// `base` with the flight's scene: its runway and radar site (checked to land within 0.5 m of
/// site.json's), azimuth reference, plot period and phase (on base's truth step), and its nav
/// track written to `work_dir`/replay.csv as the trajectory. ConfigError where the flight does
/// not fit the scenario's ranges (e.g. a radar site beyond 5 km of the threshold).
Scenario scenario_of_flight(const PrlFlightData& f, Scenario base, const std::string& work_dir);

/// The extended model of a flight: `sc` (scenario_of_flight's) with the report's named effects
/// (prl_effects_from_report) and its nominal fit's constant biases (range_bias [m],
/// azimuth_bias and elevation_bias [rad]) as the radar's constant systematic errors. The
/// diagnosis's bias holds at the flight's first plot, the simulation's at its start (the nav
/// track's first sample, sim time 0): with a bias_drift d the simulated constant is
/// b - d (t_first_plot - t_nav_start). A report without those entries is a ConfigError.
Scenario extended_scenario(const PrlFlightData& f, Scenario sc, const nlohmann::json& report, const std::string& source);

/// The landing scenario of a flight as a file that scripts/run runs as separate processes:
/// out_dir/replay.csv (the nav track) and out_dir/scenario.json (kind "prl", every option, its
/// trajectory.replay_csv "replay.csv", relative to the file); `sc` is scenario_of_flight's
/// (written with work_dir = out_dir) or extended_scenario's. Returns the scenario file's path.
std::string write_flight_scenario(const Scenario& sc, const std::string& out_dir);

/// The statistics of `runs` simulated flights (realizations 0 .. runs - 1 of `seed`) of
/// scenario sc, each exported into work_dir and read back.
std::vector<SceneStats> simulated_flight_stats(const Scenario& sc, int runs, std::int64_t seed, const std::string& work_dir);

}  // namespace rnav
