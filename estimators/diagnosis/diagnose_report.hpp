// The report of a single-sensor diagnosis (landing radar, azimuth-only): what the effect-search
// engine found (../model_id/effect_search.hpp), in the shape the command line, the JSON and the
// plots use. Both adapters fill it from the engine's result with add_search_findings(); only
// what is sensor-specific (nominal parameters, the gain against truth, plot rows) is theirs.
#pragma once

#include "common/io/csv_columns.hpp"
#include "estimators/model_id/effect_search.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace rnav {

struct EffectResult {
  std::string name;
  std::string channel;                    ///< noise findings: the channel they describe ("" for mean effects)
  std::vector<double> estimate, stderr_;  ///< one per parameter (see the catalogue's units)
  std::vector<std::string> params;        ///< parameter names; a scanned effect's scanned value comes first
  double evidence_lr = 0;                 ///< 2 log likelihood ratio against the model without it
  double log10_p = 0;                     ///< log10 of its adjusted p-value (familywise; scans included)
  /// The 2 log LR the selection kept it with (given the other effects; the least over the noise
  /// confidence sets, FoundEffect::kept_lr) and its adjusted log10 p.
  double kept_lr = 0, kept_log10_p = 0;  ///< (mean effects only; channel empty)
  double delta_bic = 0;                   ///< BIC(without) - BIC(with): > 10 is very strong
  std::vector<std::string> confounded_with;
  std::string note;
  bool nominal = false;                   ///< a parameter of the nominal model, not an effect
};

struct ChannelGain {
  int n = 0;
  std::string unit;                                ///< the channel's unit ("m", "rad")
  double nominal_rms = 0, extended_rms = 0;        ///< [channel unit] held-out residual RMS
  double nominal_loglik = 0, extended_loglik = 0;  ///< held-out predictive log-likelihood (0: not scored)
};

struct DiagnoseReport {
  std::string kind = "prl";  ///< "prl" (landing radar) or "uav" (azimuth-only)
  std::string reference;     ///< uav: what the residuals are taken against (truth or fitted track)
  std::vector<EffectResult> effects;
  /// Held-out gain per channel ("range", "course", "glide"; "bearing") and against truth
  /// ("truth_position_m") where the adapter can score one.
  std::map<std::string, ChannelGain> gain;
  std::vector<std::string> gain_effects;  ///< the named effects the estimation window determines (used in the gain)
  nlohmann::ordered_json gain_fit;        ///< their estimates and SEs on the estimation window (search_json.hpp)
  std::string gain_fit_line;              ///< the same on one line, for text()
  std::vector<std::string> unexplained;
  /// limits_method, detection_limits, naming_limits, fisher_limits, injected_limits
  /// (search_json.hpp's limits_json; keys by name, scope "common" dropped).
  nlohmann::ordered_json limits;
  /// The same given the entry it is hardest to tell apart from (search_json.hpp's separation_json).
  nlohmann::ordered_json separation_limits;
  nlohmann::ordered_json noise;  ///< per channel: the identified noise model
  std::string familywise;        ///< the stated selection rule
  int plots_used = 0, plots_dropped = 0;
  double split_time_s = 0;
  /// Per plot: time, residual and the nominal and extended models' fits (full data).
  /// uav: y = (bearing residual [rad], bearing rate [rad/s], range [m]); fits in channel 0.
  struct Row {
    double t_s;
    std::array<double, 3> y, nominal, extended;
    bool outlier;
  };
  std::vector<Row> rows;
  /// Write rows as CSV, and the description of its columns beside it (FILE without .csv +
  /// ".units.json", csv_columns.hpp). prl: t_s, then per channel residual, nominal, extended;
  /// outlier flag. uav: t_s,bearing_residual_rad,bearing_extended_rad,bearing_rate_radps,range_m,outlier.
  void write_residuals_csv(const std::string& file) const;
  /// The columns write_residuals_csv writes for this report's kind (unit and meaning of each).
  std::vector<CsvColumnDoc> residuals_columns() const;
  nlohmann::ordered_json to_json() const;
  std::string text() const;
};

/// Append the engine's findings to rep: the named effects (a scanned entry's value first among
/// its parameters; a (sin_X, cos_X) pair reported as amplitude_X), the named noise findings per
/// channel (noise_scale, correlated_noise, outliers), detection limits (keyed by name; scope
/// "common" dropped), the held-out gain per channel, unexplained structure, the noise models
/// and the familywise rule.
void add_search_findings(const Problem& pb, const SearchResult& r, DiagnoseReport& rep);

/// Refuse (ConfigError naming `who` and the name) an entry in io.entries (--limits-for) that
/// selects no catalogue entry of pb: checked before the search, not after minutes of it.
void check_limit_entries(const Problem& pb, const InjectionOptions& io, const std::string& who);

/// Per observation of pb: is it flagged as an outlier by its channel's noise identification?
std::vector<char> outlier_flags(const Problem& pb, const SearchResult& r);

}  // namespace rnav
