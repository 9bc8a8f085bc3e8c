// What every process of the landing scenario shares besides its own options: the site (runway
// and radar, i.e. the frames L and R) and the lock-step runner (whose epoch maps sim time to
// utime). Nodes and libraries take their own options plus this; the composed scenario
// (scripts/compose/scenario/scenario.hpp) makes it.
#pragma once

#include "common/physics/frames.hpp"
#include "common/node/runner_options.hpp"
#include "common/physics/sim_time.hpp"
#include "common/io/site_options.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace rnav {

struct SiteContext {
  RunwayOptions runway;
  RadarSiteOptions radar;  ///< azimuth_reference_deg resolved (not -1)
  RunnerOptions runner;

  /// Landing frame L at the threshold.
  LocalLevelFrame landing_frame() const;
  /// The radar site on WGS84.
  Geodetic radar_site() const;
  /// Radar frame R at the site, x along radar.azimuth_reference_deg.
  LocalLevelFrame radar_frame() const;
  /// Sim time [us] -> utime [us since Unix epoch].
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }
};

/// The shared sections of a landing scenario document (runway, radar, runner), read strictly
/// (an unknown key or bad value in them is a ConfigError naming it; other sections are not
/// read), radar.azimuth_reference_deg's default resolved. For readers of recorded runs.
SiteContext read_site_context(const nlohmann::json& doc);

/// The runner section of a scenario document, read strictly as above (other sections not read).
RunnerOptions read_runner_options(const nlohmann::json& doc);

}  // namespace rnav
