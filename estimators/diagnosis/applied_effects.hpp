// Hardware effects applied to a recording at given values, and the error per sensor:target pair
// without and with them: the leave-one-recording-out validation (values fitted on the other
// recordings) and the calibration check (`rnav_diagnose multi DIR... --apply FILE`: values from
// a file, e.g. a diagnosis JSON of other recordings, or a lab calibration).
//
// Pair error: position error of a detection against its reference [m] for range sensors
// (hypot(range error, range x bearing error)), bearing error [deg] for bearing-only sensors;
// a pair's figure is the RMS over its detections.
#pragma once

#include "estimators/diagnosis/multi_association.hpp"
#include "estimators/diagnosis/multi_problem.hpp"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace rnav {

/// One recording's error per sensor:target pair, nominal and with the effects removed.
struct LeaveOneOutRow {
  std::string recording, pair;  ///< pair = "sensor:target"
  int n = 0;                    ///< detections of the pair
  double nominal_rms = 0, extended_rms = 0;  ///< [unit] RMS pair error, nominal / with the effects
  std::string unit;             ///< "m" (position error) or "deg" (bearing error)
};

/// Ratios extended / nominal over the pairs with at least min_n detections.
struct LeaveOneOutSummary {
  int min_n = 5, pairs = 0;
  double geomean = 0;           ///< geometric mean of extended / nominal RMS
  double worst = 0;             ///< the largest ratio
  std::string worst_key;        ///< "recording sensor:target"
};
LeaveOneOutSummary summarize(const std::vector<LeaveOneOutRow>& rows, int min_n = 5);

/// The per-pair sums behind LeaveOneOutRow (and the held-out gain of one fit).
struct PairErrors {
  struct Sums {
    int n = 0;
    double nominal = 0, extended = 0;  ///< sums of squared pair errors
    std::string unit;
  };
  std::map<std::string, Sums> sums;
  /// One detection of pair `key`: bearing errors eb0 (nominal) and eb1 (extended) [rad] and,
  /// for a range sensor (`range`), range errors er0, er1 [m].
  void add(const std::string& key, const AssociatedDetection& x, double eb0, double eb1, bool range, double er0, double er1);
  /// Per pair: n, nominal and extended RMS, unit.
  std::vector<LeaveOneOutRow> rows(const std::string& recording) const;
};

/// A hardware effect at a given value: a catalogue entry without a recording (multi_problem.hpp).
struct AppliedEffect {
  std::string name;              ///< catalogue name, e.g. "time_offset", "antenna_offset"
  std::string sensor, target;    ///< its scope (empty: not scoped by it), as in the diagnosis JSON
  std::vector<double> value;     ///< one per parameter, in the catalogue's units (s, rad, m, 1)
  /// scanned entries (scan_time_offset): the grid value of the scanned parameter (e.g. the
  /// sweep's end bearing [deg]); NaN for entries without a scan
  double scan_value = NAN;
  /// "name@scope" (Scope::label without a recording), e.g. "time_offset@sensor radar"
  std::string key() const;
  /// "name@scope (param=value ...)" as the reports print it
  std::string label(const std::vector<std::string>& params, const std::string& scan_param) const;
};

/// One recording scored with effects removed.
struct AppliedScore {
  std::vector<LeaveOneOutRow> rows;         ///< per sensor:target pair
  std::vector<std::string> applied;         ///< the label of each effect applied (observations here)
  std::vector<char> used;                   ///< per effect given: 1 if applied here
  std::set<std::string> catalogue_names;    ///< the names of this recording's catalogue entries
};

/// One recording's problem built once (the costly part: its catalogue's columns) and scored with
/// any number of calibrations. scan_period_s: per range sensor, as the effects were fitted with
/// (it sets which sensors have a scan stamp entry).
class AppliedScorer {
 public:
  AppliedScorer(const RecordingDetections& rec, const std::map<std::string, double>& scan_period_s,
                const MultiProblemOptions& po);
  /// The recording's detections scored with the effects removed (those with observations in
  /// it). Throws ConfigError when an effect's value count or scan value does not fit its
  /// catalogue entry.
  AppliedScore score(const std::vector<AppliedEffect>& effects) const;
  /// Per effect: its prediction on each of the recording's observations (what score() removes),
  /// or an empty vector when the recording has none of its observations; `labels` (optional)
  /// gets the label of each effect with observations here. Throws as score().
  std::vector<Eigen::VectorXd> predictions(const std::vector<AppliedEffect>& effects,
                                           std::vector<std::string>* labels = nullptr) const;
  /// The rows of score() with `pred` (one value per observation, e.g. a sum of predictions())
  /// removed.
  std::vector<LeaveOneOutRow> rows(const Eigen::VectorXd& pred) const;
  std::size_t observations() const { return mp_.problem.size(); }

 private:
  RecordingDetections rec_;
  MultiProblem mp_;
  std::set<std::string> catalogue_names_;
  // per scored detection (one with a bearing observation): its pair (index into pairs_), its
  // observations (range -1 for a bearing-only sensor) and measured range [m]
  struct Scored {
    std::size_t pair;
    long ib, ir;
    double range_m;
  };
  std::vector<Scored> scored_;
  std::vector<std::string> pairs_;  ///< "sensor:target", sorted
  std::vector<int> pair_n_;          ///< detections per pair
};

/// A calibration file read: its hardware effects, and what it holds besides.
struct Calibration {
  std::vector<AppliedEffect> effects;  ///< hardware: applied
  std::vector<std::string> own;        ///< one recording's own effects ("name@scope in REC"): not applied
  int findings = 0;                    ///< noise findings and reference-track manoeuvres: not corrections, not applied
  /// a diagnosis JSON's hardware effects not carried (share 0, or named but not taken by the
  /// carried fit): "name@scope"
  std::vector<std::string> withheld;
};

/// Reads {"effects": [{"name", "scope": {"sensor", "target"}, "estimate": number or list,
/// "replication": {"mean": ...} (optional, preferred when present: the value the leave-one-out
/// carries), "scanned": {"value"} (scanned entries)}, ...]}: the diagnosis JSON's own form, so a
/// pooled diagnosis of some recordings checks on others. Bad input (not an object, no effects
/// list, a name or scope not a string, a value not a finite number) throws ConfigError naming
/// `where` and the effect. A diagnosis JSON's "carry" (carry_rule.hpp: carry_json), when present,
/// gives the hardware effects instead: each of its effects at its carried "estimate", none at
/// share 0; those, and named hardware it lacks (the carried fit may be at another level), are
/// listed in `withheld`; a bad share or estimate throws ConfigError.
Calibration read_calibration(const nlohmann::json& doc, const std::string& where);

/// Reads a file of several calibrations, {"calibrations": [{"effects": [...]}, ...]} (one or
/// more, each as read_calibration, named "calibrations[i]" in errors), or one calibration as
/// read_calibration reads it: a list of one. A file with both keys, or an empty list, throws.
std::vector<Calibration> read_calibrations(const nlohmann::json& doc, const std::string& where);

}  // namespace rnav
