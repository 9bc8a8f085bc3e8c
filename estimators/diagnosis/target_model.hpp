// The target's motion model is part of the model under test: each reference track (truth) is
// checked against the simulation's target model, constant velocity between scripted
// manoeuvres. Channels "<target>:north" and "<target>:east" [m] (samples at least
// min_spacing_s apart); nuisance: position and velocity per axis (the CV track); catalogue:
// target_maneuver (a velocity change dv_north, dv_east [m/s] at a scanned time, up to
// max_maneuvers per target), selected by the effect-search engine under the identified noise.
#pragma once

#include "estimators/model_id/effect_search.hpp"
#include "common/physics/frames.hpp"

#include <map>
#include <string>
#include <vector>

namespace rnav {

struct TargetModelOptions {
  SearchOptions search;
  double min_spacing_s = 0.5;     ///< [s] thinning of the reference samples, > 0
  double nominal_sigma_m = 0.1;   ///< [m] nominal reference (GNSS) noise, > 0
  int grid = 30;                  ///< manoeuvre-time grid (10 % to 90 % of the span), >= 2
  int max_maneuvers = 3;          ///< per target, >= 1
  /// [m] a reference track within this RMS of a straight constant-velocity line on both axes is
  /// constant velocity to the precision it was written with (a simulated track: round-off of
  /// ~1e-9 m in memory, ~1e-6 m through a CSV) and is not searched: the noise model's scale is
  /// profiled, so round-off structure would otherwise pass for a manoeuvre of 1e-10 m/s; > 0
  double resolution_m = 1e-3;
  int threads = 1;                ///< targets searched at once (each alone; same result whatever), >= 1
};

struct TargetModelResult {
  std::vector<FoundEffect> maneuvers;   ///< name target_maneuver, scope {"", target}
  std::vector<std::string> notes;       ///< per target: the track's noise model
};

/// frame: local level frame (x north, z east); truth: per target, time order.
TargetModelResult test_target_model(const std::map<std::string, std::vector<GeoSample>>& truth,
                                    const LocalLevelFrame& frame, const TargetModelOptions& o);

}  // namespace rnav
