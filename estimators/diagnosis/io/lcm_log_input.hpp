// Diagnose input from an LCM event log of a simulation run (`scripts/run --lcm-log FILE`,
// lcm-logger, or LcmLogTap): one realization becomes the same PrlFlightData / AzimuthData that
// the CSV interchange format gives, so diagnose works the same on simulated logs, CSV folders
// and LCM logs. The streams are checked for loss, duplication and order (LcmLogStreams).
//
//   prl: TRUTH_AIRCRAFT -> truth, PRL_APOI -> plots, NAV_SOLUTION -> nav (time of validity);
//        site (radar, azimuth reference, threshold, heading) from the scenario.
//   uav: UAV_NAV -> observer (what the UAV believes: its navigation solution, as observer.csv),
//        UAV_BEARING -> frames (detections sharing a time stamp form one frame),
//        TRUTH_TARGET -> truth.
// Times are (utime - runner.epoch_utime) * 1e-6 s. The scenario comes from --scenario FILE if
// given, else from the log's SIM_SCENARIO message (published by the clock before every
// realization); --set overrides apply to either. Neither available: an error saying so.
#pragma once

#include "estimators/diagnosis/azimuth_data.hpp"
#include "estimators/diagnosis/prl_flight_data.hpp"

#include <string>
#include <vector>

namespace rnav {

struct LcmLogOptions {
  int realization = 0;                 ///< which realization of the log (--realization)
  std::string scenario_file;           ///< --scenario; empty: the log's SIM_SCENARIO
  std::vector<std::string> overrides;  ///< --set key=value, applied to the scenario used
};

/// @param summary  if not null, receives one line: what was read, used and ignored.
PrlFlightData read_prl_lcm_log(const std::string& file, const LcmLogOptions& o,
                               std::string* summary = nullptr);
AzimuthData read_uav_lcm_log(const std::string& file, const LcmLogOptions& o,
                             std::string* summary = nullptr);

}  // namespace rnav
