// The landing-approach scenario: every process's options composed into one file.
//
// One JSON file configures all processes; each process loads the whole file (so a misspelt
// key anywhere is an error in every process, naming it) and hands each node its own sections
// plus the shared site context (site()). Each section's options, with unit, default and range,
// live with the module they configure (e.g. sim/prl/prl_options.hpp); this composition reads
// them in file order and checks what spans sections.
// Defaults reproduce the paper's conditions (docs/method.md) plus the documented
// choices for what the paper leaves open (speed, lateral path, radar site, airfield).
#pragma once

#include "sim/datalink/datalink_options.hpp"
#include "loggers/logger_options.hpp"
#include "estimators/prl_bias/prl_bias_options.hpp"
#include "sim/prl/prl_options.hpp"
#include "common/node/runner_options.hpp"
#include "common/node/site_context.hpp"
#include "common/io/site_options.hpp"
#include "sim/snsins/snsins_options.hpp"
#include "sim/trajectory/trajectory_options.hpp"

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace rnav {

struct Scenario {
  std::string name = "paper";
  RunwayOptions runway;
  RadarSiteOptions radar;
  TrajectoryOptions trajectory;
  PrlOptions prl;
  PrlEffectsOptions prl_effects;
  SnsinsOptions snsins;
  DatalinkOptions datalink;
  PrlBiasOptions prl_bias;
  LoggerOptions logger;
  RunnerOptions runner;
  /// Top-level key "prl_effects_report": a landing-radar diagnosis report (rnav_diagnose prl
  /// --json) whose named effects become prl_effects (prl_report.hpp), instead of that section's
  /// keys (giving both is an error). A relative path in the file is relative to the file's
  /// directory, one given by an override (--set) to the working directory. load() applies it
  /// and clears it, so the printed scenario holds the values simulated.
  std::string prl_effects_report;

  /// Load and validate a scenario file with "a.b=value" overrides applied first.
  /// Throws ConfigError naming the key for unknown keys, wrong types, NaN, out-of-range values
  /// and inconsistent combinations.
  static Scenario load(const std::string& file, const std::vector<std::string>& overrides = {});
  /// Parse from an already-loaded JSON document.
  static Scenario from_json(const nlohmann::json& doc);

  /// What every node shares: runway, radar site, runner.
  SiteContext site() const { return SiteContext{runway, radar, runner}; }
  /// Landing frame L at the threshold.
  LocalLevelFrame landing_frame() const { return site().landing_frame(); }
  /// The radar site on WGS84.
  Geodetic radar_site() const { return site().radar_site(); }
  /// Radar frame R at the site, x along radar.azimuth_reference_deg.
  LocalLevelFrame radar_frame() const { return site().radar_frame(); }

  /// Sim time [us] -> utime [us since Unix epoch].
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }

  /// The lock-step nodes a multi-process run starts, in the chain's order, each the process
  /// rnav_<name>: trajectory, snsins, datalink (only when datalink.enabled), prl, prl_bias, logger.
  /// scripts/run takes them from `rnav_clock --print-nodes`.
  std::vector<std::string> node_names() const;

  /// Human-readable dump of every option (printed by every process at start-up).
  void print(std::ostream& os) const;
  /// print()'s text: the effective scenario (what the loggers write as scenario.json).
  std::string json_text() const;
};

}  // namespace rnav
