// The multi-sensor diagnosis posed to the effect-search engine: channels, residuals, the
// catalogue with its scopes, covariates and scope questions (multi_diagnose.hpp lists them),
// for one recording or several diagnosed together.
#pragma once

#include "estimators/model_id/effect_search.hpp"
#include "estimators/diagnosis/multi_association.hpp"

#include <map>
#include <string>
#include <vector>

namespace rnav {

/// One recording's associated detections.
struct RecordingDetections {
  std::string name;  ///< recording name (e.g. its folder's name); empty when there is one recording
  std::vector<AssociatedDetection> a;
};

struct MultiProblemOptions {
  double sigma_bearing_rad = 0.5 * M_PI / 180;  ///< [rad] nominal bearing noise, > 0
  double sigma_range_m = 1;                     ///< [m] nominal range noise of range sensors, > 0
  double split_fraction = 0.6;                  ///< estimation window = first fraction of each recording's span, (0.2, 0.9)
  int step_grid = 24;                           ///< grid of bias_step (10 % to 90 % of a recording's span), >= 2
  int sweep_grid = 24;                          ///< grid of scan_time_offset's sweep-end bearing over [0, 360) deg, >= 2
  /// [s] a range sensor whose median interval between scans is at least this gets a
  /// scan_time_offset entry (a rotating radar whose scan carries one stamp), > 0. (At 0.5 s the
  /// Autoferry lidar, 0.504 s between scans, drew a sweep share of -5 in scenario 4 where a
  /// stamp can give at most 1: a slow drift, not its sweep.)
  double min_sweep_period_s = 1.0;
  /// [s] per range sensor: its scan period (the median interval between its scans, measured by
  /// the caller over every recording; a recording scored with a model fitted on others takes
  /// theirs); each > 0. A range sensor without one gets no scan_time_offset.
  std::map<std::string, double> scan_period_s;
  /// per target: its hull size (targets.csv), which bounds its antenna and hull offsets; a
  /// target without one (or with a NaN) is bounded by the max_hull sizes below
  std::map<std::string, HullSize> hull;
  double max_hull_length_m = 400;  ///< [m] a target of unknown length is at most this long (the largest ships afloat), > 0
  double max_hull_beam_m = 62;     ///< [m] and at most this wide, > 0
  /// [s] a target reference's clock offset (truth_time_offset) is at most this: a GNSS or AIS
  /// position is stamped with its fix's time (AIS: its UTC second, so up to 1 s, and a
  /// receiver's stamping delay of a second or two); a larger fitted value stands in for
  /// something else (on a harbour radar, the echo's place along a long hull) and is refused, > 0
  double max_reference_clock_s = 3;
};

struct MultiProblem {
  Problem problem;
  /// per recording, per associated detection: its observation index (-1: none)
  std::vector<std::vector<long>> bearing_obs, range_obs;
  std::vector<double> split_time_s;           ///< per recording
  std::map<std::string, double> scan_period_s;  ///< MultiProblemOptions::scan_period_s, as used
  std::vector<std::string> dropped_channels;  ///< "name (n detections)": fewer than 10, not used
};

/// Channels per recording (a channel's noise is that recording's); hardware entries (one value
/// in every recording) and per-recording entries as multi_diagnose.hpp lists; with more than
/// one recording, each hardware kind also gets a scope question against its per-recording
/// values (scope_only entries). Recording names must be distinct.
MultiProblem build_multi_problem(const std::vector<RecordingDetections>& recs, const MultiProblemOptions& o);

// scan_time_offset shifts a measurement h of a scanning sensor whose scan is stamped at the end
// of its sweep by dh = -(dh/dd v_rel) [c + f sweep_delay_s(beta, beta_end, T)] (scan_stamp.hpp),
// c [s] a constant delay, f [1] the sweep's share (1: one stamp per scan at its end, clockwise;
// -1: counter-clockwise, with c absorbing T).

}  // namespace rnav
