// The values a pooled fit's hardware effects are carried to a recording it was not fitted on
// (the leave-one-out's folds, and the diagnosis JSON's `carry` that --apply uses).
//
// The random-effects mean over the recordings is the best guess of a new recording's value, but
// the recordings' own values spread (Autoferry: the lidar's clock about 0.7 s on average, about
// 0 s on one boat in one recording), and a carried value c lowers a recording's error only while
// it lies between 0 and twice that recording's own value. "Do no harm where it was fitted": each
// hardware effect's value is scaled by a share in [0, 1] (a grid), the shares chosen together for
// the lowest geometric mean of error ratios over the fitted recordings' sensor:target pairs, among
// the choices that leave no such pair worse than `tolerance` x. A pair's ratio compares its error
// with the carried hardware and that recording's own fitted effects (a reference clock, a start-up
// bias) removed against its error with its own effects alone: a recording's own effects are known
// where it was fitted (and may mask the hardware's there), never carried. Every share 0 (nothing
// carried) always qualifies, so the rule never fails.
#pragma once

#include "estimators/diagnosis/applied_effects.hpp"

#include <string>
#include <vector>

namespace rnav {

struct CarryOptions {
  /// [1] the most a carried calibration may raise any pair (with at least min_n detections) of
  /// the recordings it was fitted on, as calibrated / nominal RMS error, >= 1; 0: no check, the
  /// random-effects means carried whole. Default 1: no such pair made worse.
  double tolerance = 1.0;
  int min_n = 5;            ///< pairs with fewer detections are not checked (as LeaveOneOutSummary), >= 1
  /// the grid of shares holds at most this many choices: 0, 0.1, ..., 1 per effect while 11^m
  /// fits (m effects), coarser beyond (at least 0 and 1 each), >= 2
  int max_choices = 1500;
};

/// Throws ConfigError naming the field when `o` is out of range.
void check_carry_options(const CarryOptions& o);

struct CarriedHardware {
  double tolerance = 0;                 ///< CarryOptions::tolerance as used
  std::vector<AppliedEffect> fitted;    ///< the hardware effects at their fitted (random-effects mean) values
  std::vector<double> share;            ///< per effect: the share carried, in [0, 1]
  std::vector<AppliedEffect> carried;   ///< the effects with share > 0, at share x fitted value
  /// the fitted recordings scored with every share 1 (each pair's ratio against its error with
  /// its recording's own effects removed)
  LeaveOneOutSummary whole;
  LeaveOneOutSummary chosen;            ///< ... with the shares chosen
  int choices = 0;                      ///< grid points tried
};

/// A recording the hardware was fitted on: its problem (built with the fit's scan periods) and
/// the fit's effects of that recording alone (AppliedEffect form, the recording's name dropped).
struct FittedRecording {
  const AppliedScorer* scorer = nullptr;
  std::vector<AppliedEffect> own;
};

/// The shares of `fitted` (hardware effects; a scanned one keeps its scanned value) chosen on
/// `recordings`. With tolerance 0 every share is 1. Deterministic: ties go to the larger shares.
/// Throws std::logic_error if a recording's own effect has no observations in it.
CarriedHardware carry_no_harm(const std::vector<AppliedEffect>& fitted, const std::vector<FittedRecording>& recordings,
                              const CarryOptions& o);

/// As JSON: {"tolerance", "choices", "fitted_recordings": {"whole": summary, "chosen": summary},
/// "effects": [{"name", "scope": {"sensor", "target"}, "share", "fitted": [...], "estimate": [...]
/// (the carried value, catalogue units), "scanned": {"value"} (scanned entries)}]}. --apply
/// (read_calibration) takes "estimate" from here.
nlohmann::ordered_json carry_json(const CarriedHardware& c);

/// One line per effect: "name@scope: share s (value ...)"; empty when nothing is fitted.
std::string carry_text(const CarriedHardware& c, const std::string& indent);

}  // namespace rnav
