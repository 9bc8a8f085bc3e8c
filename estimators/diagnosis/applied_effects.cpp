#include "estimators/diagnosis/applied_effects.hpp"

#include "common/io/config.hpp"
#include "common/physics/frames.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>

namespace rnav {

LeaveOneOutSummary summarize(const std::vector<LeaveOneOutRow>& rows, int min_n) {
  LeaveOneOutSummary s;
  s.min_n = min_n;
  double sum_log = 0;
  for (const auto& x : rows) {
    if (x.n < min_n || !(x.nominal_rms > 0)) continue;
    const double ratio = x.extended_rms / x.nominal_rms;
    sum_log += std::log(ratio);
    ++s.pairs;
    if (ratio > s.worst) s.worst = ratio, s.worst_key = x.recording + " " + x.pair;
  }
  s.geomean = s.pairs > 0 ? std::exp(sum_log / s.pairs) : NAN;
  return s;
}

namespace {

// One detection's pair error: a range sensor's position error e = hypot(range error, range x
// bearing error) [m]; a bearing-only sensor's bearing error [deg]. eb [rad], er [m], range_m [m].
double pair_error(bool range, double range_m, double eb, double er) {
  return range ? std::hypot(er, range_m * eb) : eb / kDegToRad;
}

}  // namespace

void PairErrors::add(const std::string& key, const AssociatedDetection& x, double eb0, double eb1, bool range, double er0,
                     double er1) {
  Sums& g = sums[key];
  const double e0 = pair_error(range, x.range_m, eb0, er0), e1 = pair_error(range, x.range_m, eb1, er1);
  g.unit = range ? "m" : "deg";
  g.nominal += e0 * e0;
  g.extended += e1 * e1;
  ++g.n;
}

std::vector<LeaveOneOutRow> PairErrors::rows(const std::string& recording) const {
  std::vector<LeaveOneOutRow> out;
  for (const auto& [k, g] : sums) {
    const double n = std::max(1, g.n);
    out.push_back({recording, k, g.n, std::sqrt(g.nominal / n), std::sqrt(g.extended / n), g.unit});
  }
  return out;
}

std::string AppliedEffect::key() const { return name + "@" + Scope{sensor, target, ""}.label(); }

std::string AppliedEffect::label(const std::vector<std::string>& params, const std::string& scan_param) const {
  std::string what = key() + " (";
  for (std::size_t j = 0; j < value.size(); ++j)
    what += (j ? " " : "") + (j < params.size() && params[j] == "1" ? std::string("ratio") : j < params.size() ? params[j] : "?") +
            "=" + short_num(value[j]);
  if (!scan_param.empty()) what += " " + scan_param + "=" + short_num(scan_value);
  return what + ")";
}

namespace {

// The grid point of entry c whose value is v (scanned entries), or the entry's only variant.
std::size_t variant_of(const Candidate& c, const AppliedEffect& e) {
  if (!c.scanned()) return 0;
  if (!std::isfinite(e.scan_value))
    throw ConfigError("calibration: " + e.name + "@" + c.scope.label() + " is scanned over " + c.scan_param +
                      ": give its value (\"scanned\": {\"value\": ...})");
  for (std::size_t v = 0; v < c.scan.size(); ++v)
    if (std::abs(c.scan[v] - e.scan_value) <= 1e-9 * std::max(1.0, std::abs(c.scan[v]))) return v;
  std::string grid;
  for (double x : c.scan) grid += (grid.empty() ? "" : ", ") + short_num(x);
  throw ConfigError("calibration: " + e.name + "@" + c.scope.label() + ": " + c.scan_param + " = " + short_num(e.scan_value) +
                    " is not on its grid (" + grid + ")");
}

}  // namespace

namespace {

MultiProblem build_one(const RecordingDetections& rec, const std::map<std::string, double>& scan_period_s,
                       const MultiProblemOptions& po_in) {
  MultiProblemOptions po = po_in;
  po.scan_period_s = scan_period_s;
  RecordingDetections one = rec;
  one.name.clear();
  return build_multi_problem({one}, po);
}

}  // namespace

AppliedScorer::AppliedScorer(const RecordingDetections& rec, const std::map<std::string, double>& scan_period_s,
                             const MultiProblemOptions& po)
    : rec_(rec), mp_(build_one(rec, scan_period_s, po)) {
  for (const Candidate& c : mp_.problem.catalogue) catalogue_names_.insert(c.name);
  std::map<std::string, std::size_t> index;  // pair -> position in pairs_ (sorted, as PairErrors::rows)
  for (std::size_t i = 0; i < rec_.a.size(); ++i)
    if (mp_.bearing_obs[0][i] >= 0) index.emplace(rec_.a[i].sensor + ":" + rec_.a[i].target, 0);
  for (auto& [key, k] : index) {
    k = pairs_.size();
    pairs_.push_back(key);
  }
  pair_n_.assign(pairs_.size(), 0);
  for (std::size_t i = 0; i < rec_.a.size(); ++i) {
    const long ib = mp_.bearing_obs[0][i], ir = mp_.range_obs[0][i];
    if (ib < 0) continue;
    const auto& x = rec_.a[i];
    const bool range = x.has_range && ir >= 0;
    const std::size_t k = index.at(x.sensor + ":" + x.target);
    scored_.push_back({k, ib, range ? ir : -1, x.range_m});
    ++pair_n_[k];
  }
}

std::vector<Eigen::VectorXd> AppliedScorer::predictions(const std::vector<AppliedEffect>& effects,
                                                        std::vector<std::string>* labels) const {
  const Problem& p = mp_.problem;
  std::vector<Eigen::VectorXd> out(effects.size());
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const AppliedEffect& e = effects[k];
    const std::string scope = Scope{e.sensor, e.target, ""}.label();
    const auto it = std::find_if(p.catalogue.begin(), p.catalogue.end(), [&](const Candidate& x) {
      return !x.scope_only && x.name == e.name && x.scope.label() == scope;
    });
    if (it == p.catalogue.end()) continue;  // the recording has none of its observations
    if (e.value.size() != it->params.size())
      throw ConfigError("calibration: " + e.name + "@" + scope + " has " + std::to_string(it->params.size()) +
                        " parameter(s), got " + std::to_string(e.value.size()) + " value(s)");
    // the effect's prediction: its columns at the grid point times its value
    const Eigen::MatrixXd C = it->columns(variant_of(*it, e));
    out[k] = C * Eigen::Map<const Eigen::VectorXd>(e.value.data(), static_cast<Eigen::Index>(e.value.size()));
    if (labels) labels->push_back(e.label(it->params, it->scan_param));
  }
  return out;
}

std::vector<LeaveOneOutRow> AppliedScorer::rows(const Eigen::VectorXd& pred) const {
  const Problem& p = mp_.problem;
  if (pred.size() != static_cast<Eigen::Index>(p.size()))
    throw std::logic_error("AppliedScorer::rows: " + std::to_string(pred.size()) + " predictions for " +
                           std::to_string(p.size()) + " observations");
  std::vector<double> nominal(pairs_.size(), 0.0), extended(pairs_.size(), 0.0);
  std::vector<char> range_pair(pairs_.size(), 0);
  for (const Scored& s : scored_) {
    const bool range = s.ir >= 0;
    const double eb0 = p.y[static_cast<std::size_t>(s.ib)], eb1 = eb0 - pred(s.ib);
    const double er0 = range ? p.y[static_cast<std::size_t>(s.ir)] : 0.0, er1 = range ? er0 - pred(s.ir) : 0.0;
    const double e0 = pair_error(range, s.range_m, eb0, er0), e1 = pair_error(range, s.range_m, eb1, er1);
    range_pair[s.pair] |= range;
    nominal[s.pair] += e0 * e0;
    extended[s.pair] += e1 * e1;
  }
  std::vector<LeaveOneOutRow> out;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double n = std::max(1, pair_n_[k]);
    out.push_back({rec_.name, pairs_[k], pair_n_[k], std::sqrt(nominal[k] / n), std::sqrt(extended[k] / n),
                   range_pair[k] ? "m" : "deg"});
  }
  return out;
}

AppliedScore AppliedScorer::score(const std::vector<AppliedEffect>& effects) const {
  AppliedScore out;
  out.catalogue_names = catalogue_names_;
  const std::vector<Eigen::VectorXd> each = predictions(effects, &out.applied);
  Eigen::VectorXd pred = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mp_.problem.size()));
  out.used.assign(effects.size(), 0);
  for (std::size_t k = 0; k < effects.size(); ++k)
    if (each[k].size() > 0) {
      pred += each[k];
      out.used[k] = 1;
    }
  out.rows = rows(pred);
  return out;
}


namespace {

std::vector<double> finite_values(const nlohmann::json& v, const std::string& what) {
  std::vector<double> out;
  const nlohmann::json list = v.is_array() ? v : nlohmann::json::array({v});
  for (const auto& x : list) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) throw ConfigError(what + ": " + x.dump() + " is not a finite number");
    out.push_back(x.get<double>());
  }
  if (out.empty()) throw ConfigError(what + ": no value");
  return out;
}

std::string string_or_null(const nlohmann::json& scope, const char* key, const std::string& what) {
  if (!scope.contains(key) || scope[key].is_null()) return "";
  if (!scope[key].is_string()) throw ConfigError(what + ": scope." + key + " must be a string or null");
  return scope[key].get<std::string>();
}

// A calibration entry's "scanned": {"value"} (scanned entries), NaN when absent; `what` names it in errors.
double scanned_value(const nlohmann::json& x, const std::string& what) {
  if (!x.contains("scanned")) return NAN;
  if (!x["scanned"].is_object() || !x["scanned"].contains("value"))
    throw ConfigError(what + ": \"scanned\" must be an object with a \"value\"");
  return finite_values(x["scanned"]["value"], what + " scanned.value").front();
}

// Entries of the engine that are not catalogue mean effects (search_json's noise findings) or
// not the multi catalogue's (the reference tracks' manoeuvres).
bool is_noise_or_track(const std::string& name) {
  return name == "noise_scale" || name == "correlated_noise" || name == "outliers" || name == "target_maneuver";
}

// A diagnosis JSON's "carry" (carry_rule.hpp's carry_json): its effects replace cal's hardware
// effects, each at its carried "estimate" (a scanned one at its "scanned" value); those at share
// 0, and the named hardware effects the carried fit did not take (it may be fitted at another
// level: MultiDiagnoseOptions::carry_alpha), go to cal.withheld.
void apply_carry(const nlohmann::json& carry, const std::string& where, Calibration& cal) {
  const std::string at = where + ": carry";
  if (!carry.is_object() || !carry.contains("effects") || !carry["effects"].is_array())
    throw ConfigError(at + ": must be an object with an \"effects\" list");
  std::vector<AppliedEffect> kept;
  std::vector<std::string> labels;
  for (const auto& x : carry["effects"]) {
    if (!x.is_object() || !x.contains("name") || !x["name"].is_string() || !x.contains("scope") || !x["scope"].is_object())
      throw ConfigError(at + ": each effect needs a \"name\" and a \"scope\"");
    AppliedEffect e;
    e.name = x["name"].get<std::string>();
    e.sensor = string_or_null(x["scope"], "sensor", at);
    e.target = string_or_null(x["scope"], "target", at);
    const std::string label = e.key();
    labels.push_back(label);
    const double share = x.contains("share") ? finite_values(x["share"], at + " (" + label + ") share").front() : NAN;
    if (!(share >= 0 && share <= 1)) throw ConfigError(at + " (" + label + "): \"share\" must be in [0, 1]");
    if (share == 0) {
      cal.withheld.push_back(label);
      continue;
    }
    if (!x.contains("estimate")) throw ConfigError(at + " (" + label + "): needs an \"estimate\"");
    e.value = finite_values(x["estimate"], at + " (" + label + ") estimate");
    e.scan_value = scanned_value(x, at + " (" + label + ")");
    kept.push_back(std::move(e));
  }
  for (const AppliedEffect& e : cal.effects)
    if (std::find(labels.begin(), labels.end(), e.key()) == labels.end()) cal.withheld.push_back(e.key());
  cal.effects = std::move(kept);
}

}  // namespace

Calibration read_calibration(const nlohmann::json& doc, const std::string& where) {
  if (!doc.is_object() || !doc.contains("effects") || !doc["effects"].is_array())
    throw ConfigError(where + ": a calibration is a JSON object with an \"effects\" list (a diagnosis JSON is one)");
  Calibration out;
  std::size_t k = 0;
  for (const auto& x : doc["effects"]) {
    const std::string at = where + ": effects[" + std::to_string(k++) + "]";
    if (!x.is_object() || !x.contains("name") || !x["name"].is_string())
      throw ConfigError(at + ": needs a \"name\" (a string)");
    AppliedEffect e;
    e.name = x["name"].get<std::string>();
    const std::string what = at + " (" + e.name + ")";
    if (!x.contains("scope") || !x["scope"].is_object()) throw ConfigError(what + ": needs a \"scope\" object");
    const auto& scope = x["scope"];
    e.sensor = string_or_null(scope, "sensor", what);
    e.target = string_or_null(scope, "target", what);
    const std::string recording = string_or_null(scope, "recording", what);
    if (is_noise_or_track(e.name)) {
      ++out.findings;
      continue;
    }
    if (!recording.empty()) {
      out.own.push_back(e.name + "@" + Scope{e.sensor, e.target, recording}.label());
      continue;
    }
    const bool has_mean = x.contains("replication") && x["replication"].is_object() && x["replication"].contains("mean");
    if (!has_mean && !x.contains("estimate")) throw ConfigError(what + ": needs an \"estimate\"");
    e.value = finite_values(has_mean ? x["replication"]["mean"] : x["estimate"], what + (has_mean ? " replication.mean" : " estimate"));
    e.scan_value = scanned_value(x, what);
    out.effects.push_back(std::move(e));
  }
  if (doc.contains("carry")) apply_carry(doc["carry"], where, out);
  return out;
}

std::vector<Calibration> read_calibrations(const nlohmann::json& doc, const std::string& where) {
  if (!doc.is_object() || !doc.contains("calibrations")) return {read_calibration(doc, where)};
  if (doc.contains("effects"))
    throw ConfigError(where + ": holds both \"effects\" (one calibration) and \"calibrations\" (several): give one");
  if (!doc["calibrations"].is_array() || doc["calibrations"].empty())
    throw ConfigError(where + ": \"calibrations\" must be a non-empty list of {\"effects\": [...]}");
  std::vector<Calibration> out;
  for (std::size_t i = 0; i < doc["calibrations"].size(); ++i)
    out.push_back(read_calibration(doc["calibrations"][i], where + ": calibrations[" + std::to_string(i) + "]"));
  return out;
}

}  // namespace rnav
