// The effect search's result as JSON and as text lines (sensor-agnostic parts of a report).
#pragma once

#include "estimators/model_id/effect_search.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace rnav {

/// {"sensor": S or null, "target": T or null}
nlohmann::ordered_json scope_json(const Scope& s);
/// An effect's evidence: "lr", "log10_p_adjusted" (GLS under the final noise, given the other
/// effects), "kept_lr", "kept_log10_p_adjusted" (the test the selection kept it with), "delta_bic".
nlohmann::ordered_json evidence_json(const FoundEffect& e);
/// "effects" (chosen effects then named noise findings), "noise" per channel, "series_gain",
/// "detection_limits", "scope_support", "unexplained", "familywise".
nlohmann::ordered_json search_json(const Problem& pb, const SearchResult& r);
/// "name@scope" -> param -> {"size": [unit] or null (no size separates them), "partner"}; strip
/// (if given) maps each key, e.g. to drop "@common".
nlohmann::ordered_json separation_json(const SearchResult& r, const std::function<std::string(const std::string&)>& strip = {});
/// The limits, one object with five members (strip as above):
///   "limits_method": "injection" (every limit measured by injection, injected_limits.hpp) or
///     "fisher" (from the Fisher information alone, SearchOptions::injection.injections = 0);
///   "detection_limits": "name@scope" -> param -> size [unit] detected (named, or stood in for by
///     a named effect that lists it as confounded) with probability `power`: the injected size
///     where measured (null: not reached within the ladder), else the Fisher size;
///   "naming_limits": the same for named itself (injection only; {} without it);
///   "fisher_limits": the Fisher sizes (non-scanned entries);
///   "injected_limits": per measured param {"fisher", "scan_value" (scanned entries), "named" and
///     "detected": {"size", "n", "hits", "cp_lo", "cp_hi"} (the check batch at the size, its
///     Clopper-Pearson interval), "ladder": [[size, n, named, detected], ...]}.
nlohmann::ordered_json limits_json(const Problem& pb, const SearchResult& r,
                                   const std::function<std::string(const std::string&)>& strip = {});
/// The extended model's held-out fit (on the estimation frames): per effect it used, its name,
/// scope, parameters, estimates and SEs, in the fit's order.
nlohmann::ordered_json gain_fit_json(const Problem& pb, const SearchResult& r);
/// The same on one line: " name@scope (param=estimate +- se ...)" per effect; "" when none.
std::string gain_fit_text(const Problem& pb, const SearchResult& r);
/// A human-readable summary (one line per finding).
std::string search_text(const Problem& pb, const SearchResult& r);

}  // namespace rnav
