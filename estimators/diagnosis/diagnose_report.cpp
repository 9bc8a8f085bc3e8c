#include "estimators/diagnosis/diagnose_report.hpp"

#include "common/io/atomic_file.hpp"

#include "common/io/config.hpp"
#include "estimators/model_id/injected_limits.hpp"
#include "estimators/model_id/search_json.hpp"
#include "estimators/model_id/shown_unit.hpp"
#include "estimators/model_id/stats.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rnav {

namespace {

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

EffectResult from_found(const FoundEffect& f) {
  EffectResult e;
  e.name = f.name;
  if (!f.scan_param.empty()) {
    e.params.push_back(f.scan_param);
    e.estimate.push_back(f.scan_value);
    e.stderr_.push_back(f.scan_se);
  }
  if (f.params.size() == 2 && starts_with(f.params[0], "sin_") && starts_with(f.params[1], "cos_")) {
    // a periodic term a sin + b cos: amplitude sqrt(a^2 + b^2); its SE by the delta method
    //   var(A) = (a^2 var(a) + b^2 var(b)) / A^2   (covariance of a, b neglected: near-orthogonal columns)
    const double a = f.estimate[0], b = f.estimate[1], A = std::hypot(a, b);
    e.params.push_back("amplitude_" + f.params[0].substr(4));
    e.estimate.push_back(A);
    const double va = f.stderr_[0] * f.stderr_[0], vb = f.stderr_[1] * f.stderr_[1];
    e.stderr_.push_back(A > 0 ? std::sqrt((a * a * va + b * b * vb) / (A * A)) : std::sqrt(0.5 * (va + vb)));
  } else {
    e.params.insert(e.params.end(), f.params.begin(), f.params.end());
    e.estimate.insert(e.estimate.end(), f.estimate.begin(), f.estimate.end());
    e.stderr_.insert(e.stderr_.end(), f.stderr_.begin(), f.stderr_.end());
  }
  e.evidence_lr = f.lr;
  e.log10_p = f.log10_p;
  e.kept_lr = f.kept_lr;
  e.kept_log10_p = f.kept_log10_p;
  e.delta_bic = f.delta_bic;
  for (const auto& c : f.confounded_with) e.confounded_with.push_back(c.name);
  e.note = f.note;
  return e;
}

std::string strip_common(const std::string& key) {
  const std::string tail = "@common";
  return key.size() > tail.size() && key.compare(key.size() - tail.size(), tail.size(), tail) == 0
             ? key.substr(0, key.size() - tail.size())
             : key;
}

}  // namespace

void add_search_findings(const Problem& pb, const SearchResult& r, DiagnoseReport& rep) {
  for (const auto& f : r.effects) rep.effects.push_back(from_found(f));
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    const ChannelNoise& n = r.noise[c];
    const Channel& ch = pb.channels[c];
    if (n.scale_named) {
      EffectResult e;
      e.name = "noise_scale";
      e.channel = ch.name;
      e.params = {"ratio"};
      e.estimate = {n.noise_scale};
      e.stderr_ = {n.noise_scale_se};
      e.log10_p = n.log10_p_scale;
      e.note = ch.name + ": fitted sigma " + short_num(std::sqrt(n.fit.params.s2)) + " " + ch.unit + " against the nominal " +
               short_num(ch.nominal_sigma) + " " + ch.unit;
      rep.effects.push_back(e);
    }
    if (n.correlated_named) {
      EffectResult e;
      e.name = "correlated_noise";
      e.channel = ch.name;
      e.params = {"tau_s", "correlated_share"};
      e.estimate = {n.fit.params.tau_s, n.fit.params.lambda};
      e.stderr_ = {n.fit.se_tau_s, 0};
      e.evidence_lr = 2 * (n.fit.loglik_correlated - n.fit.loglik_white);
      e.note = ch.name + ": " + n.fit.params.kind() + " noise (REML); every mean effect is tested under it";
      rep.effects.push_back(e);
    }
    if (n.outliers_named) {
      EffectResult e;
      e.name = "outliers";
      e.channel = ch.name;
      e.params = {"fraction"};
      const double p = n.fit.params.p_out;
      e.estimate = {p};
      e.stderr_ = {std::sqrt(p * (1 - p) / std::max(1, n.fit.n))};
      e.evidence_lr = 2 * n.outlier_gain;
      e.note = ch.name + ": frames beyond " + short_num(n.fit.z_outlier) +
               " sigma of their prediction; the outlier mixture raises the held-out log-likelihood by " +
               short_num(n.outlier_gain);
      rep.effects.push_back(e);
    }
  }
  rep.limits = limits_json(pb, r, strip_common);
  rep.separation_limits = separation_json(r, strip_common);
  for (std::size_t c = 0; c < r.gain.size(); ++c) {
    const SeriesGain& s = r.gain[c];
    if (s.n == 0) continue;
    rep.gain[pb.channels[c].name] = {s.n, pb.channels[c].unit, s.nominal_rms, s.extended_rms, s.nominal_loglik, s.extended_loglik};
  }
  rep.gain_effects = r.holdout_effects;
  rep.gain_fit = gain_fit_json(pb, r);
  rep.gain_fit_line = gain_fit_text(pb, r);
  rep.unexplained.insert(rep.unexplained.end(), r.unexplained.begin(), r.unexplained.end());
  rep.noise = search_json(pb, r)["noise"];
  rep.familywise = r.familywise;
}

void check_limit_entries(const Problem& pb, const InjectionOptions& io, const std::string& who) {
  const std::string bad = unknown_injection_entry(pb, io);
  if (!bad.empty())
    throw ConfigError(who + ": --limits-for: no catalogue entry '" + bad + "' (give name, name@scope, or either with :param)");
}

std::vector<char> outlier_flags(const Problem& pb, const SearchResult& r) {
  std::vector<char> out(pb.size(), 0);
  std::vector<std::size_t> pos(pb.channels.size(), 0);
  for (std::size_t i = 0; i < pb.size(); ++i) {
    const auto c = static_cast<std::size_t>(pb.channel[i]);
    const auto& flags = r.noise[c].fit.outlier;
    out[i] = pos[c] < flags.size() && flags[pos[c]];
    ++pos[c];
  }
  return out;
}

std::vector<CsvColumnDoc> DiagnoseReport::residuals_columns() const {
  if (kind == "uav") {
    const std::string ref = "the object's reference (truth, or the track fitted to the bearings)";
    return {{"t_s", "s", "frame time, the data set's time scale"},
            {"bearing_residual_rad", "rad", "measured bearing (the frame's detection nearest the prediction) minus the bearing to " + ref},
            {"bearing_extended_rad", "rad", "the extended model's fit to the bearing residual (the named effects)"},
            {"bearing_rate_radps", "rad/s", "rate of change of the bearing from the observer to " + ref},
            {"range_m", "m", "horizontal range from the observer to " + ref},
            {"outlier", "", "1 if the noise identification flags the frame an outlier, else 0"}};
  }
  struct Ch {
    const char* name;
    const char* unit;
    const char* text;
  };
  const Ch channels[3] = {{"range", "m", "slant range"}, {"course", "rad", "course (azimuth)"}, {"glide", "rad", "glide (elevation)"}};
  std::vector<CsvColumnDoc> c{{"t_s", "s", "plot time, the flight's time scale"}};
  for (const Ch& ch : channels) {
    const std::string unit = ch.unit, text = ch.text, base = std::string(ch.name) + "_";
    c.push_back({base + unit, unit, text + " residual: the radar's minus the nav solution's (interpolated to the plot)"});
    c.push_back({base + "nominal_" + unit, unit, "the nominal model's fit to the " + text + " residual (constant bias)"});
    c.push_back({base + "extended_" + unit, unit, "the extended model's fit to the " + text + " residual (bias and the named effects)"});
  }
  c.push_back({"outlier", "", "1 if the noise identification flags the plot an outlier (in any channel), else 0"});
  return c;
}

void DiagnoseReport::write_residuals_csv(const std::string& file) const {
  const auto columns = residuals_columns();
  std::ostringstream f;
  f << csv_header(columns);
  char b[512];
  if (kind == "uav") {
    for (const auto& r : rows) {
      std::snprintf(b, sizeof b, "%.3f,%.9f,%.9f,%.9f,%.3f,%d\n", r.t_s, r.y[0], r.extended[0], r.y[1], r.y[2],
                    r.outlier ? 1 : 0);
      f << b;
    }
  } else {
    for (const auto& r : rows) {
      std::snprintf(b, sizeof b, "%.3f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%d\n", r.t_s, r.y[0], r.nominal[0],
                    r.extended[0], r.y[1], r.nominal[1], r.extended[1], r.y[2], r.nominal[2], r.extended[2],
                    r.outlier ? 1 : 0);
      f << b;
    }
  }
  if (!f.flush()) throw ConfigError("cannot write " + file + " (disk full?)");
  write_file_atomic(file, f.str());
  write_csv_units(file, columns);
}

nlohmann::ordered_json DiagnoseReport::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = kind;
  j[kind == "uav" ? "frames_used" : "plots_used"] = plots_used;
  j[kind == "uav" ? "frames_dropped" : "plots_dropped"] = plots_dropped;
  if (!reference.empty()) j["reference"] = reference;
  j["effects"] = nlohmann::ordered_json::array();
  for (const auto& e : effects) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    if (!e.channel.empty()) x["channel"] = e.channel;
    x["params"] = e.params;
    x["estimate"] = e.estimate.size() == 1 ? nlohmann::ordered_json(e.estimate[0]) : nlohmann::ordered_json(e.estimate);
    x["stderr"] = e.stderr_.size() == 1 ? nlohmann::ordered_json(e.stderr_[0]) : nlohmann::ordered_json(e.stderr_);
    x["evidence"] = {{"lr", e.evidence_lr}, {"log10_p_adjusted", e.log10_p}};
    if (e.channel.empty() && !e.nominal) x["evidence"]["kept_lr"] = e.kept_lr, x["evidence"]["kept_log10_p_adjusted"] = e.kept_log10_p;
    x["evidence"]["delta_bic"] = e.delta_bic;
    x["confounded_with"] = e.confounded_with;
    x["nominal"] = e.nominal;
    if (!e.note.empty()) x["note"] = e.note;
    j["effects"].push_back(x);
  }
  j["noise"] = noise;
  j["gain"] = nlohmann::ordered_json::object();
  j["gain_window"] = "fit on t < " + short_num(split_time_s) + " s, scored on t >= " + short_num(split_time_s) + " s";
  j["gain_effects"] = gain_effects;
  j["gain_fit"] = gain_fit;
  for (const auto& [k, g] : gain)
    j["gain"][k] = {{"n", g.n}, {"nominal_rms", g.nominal_rms}, {"extended_rms", g.extended_rms},
                    {"nominal_loglik", g.nominal_loglik}, {"extended_loglik", g.extended_loglik}};
  j["unexplained"] = unexplained;
  for (const auto& [k, v] : limits.items()) j[k] = v;
  j["separation_limits"] = separation_limits;
  j["familywise"] = familywise;
  return j;
}

std::string DiagnoseReport::text() const {
  std::ostringstream o;
  if (kind == "uav")
    o << "frames used " << plots_used << ", dropped (no detection within the gate, or no observer or reference sample around them) " << plots_dropped
      << "\n  reference: " << reference << "\n";
  else
    o << "plots used " << plots_used << ", dropped (no nav around them) " << plots_dropped << "\n";
  for (const auto& e : effects) {
    o << (e.nominal ? "  nominal  " : "  EFFECT   ") << e.name << (e.channel.empty() ? "" : " [" + e.channel + "]") << ":";
    for (std::size_t i = 0; i < e.estimate.size(); ++i) {
      const ShownUnit u = shown_unit(i < e.params.size() ? e.params[i] : "");
      o << " " << (u.name.empty() ? "" : u.name + "=") << short_num(u.factor * e.estimate[i]) << " +- "
        << short_num(u.factor * e.stderr_[i]);
    }
    if (!e.nominal) {
      o << "  (2 log LR " << short_num(e.evidence_lr) << ", log10 p " << short_num(e.log10_p);
      if (e.channel.empty()) o << "; kept at " << short_num(e.kept_lr) << ", log10 p " << short_num(e.kept_log10_p);
      o << ")";
    }
    if (!e.confounded_with.empty()) o << "  confounded with " << e.confounded_with.front();
    o << "\n";
  }
  for (const auto& [k, g] : gain) {
    const ShownUnit u = shown_unit(g.unit);
    o << "  gain " << k << ": RMS " << short_num(u.factor * g.nominal_rms) << " -> " << short_num(u.factor * g.extended_rms)
      << (u.name.empty() ? "" : " " + u.name) << " (n " << g.n << ")\n";
  }
  if (!gain.empty()) {
    o << "  gain window: fit on t < " << short_num(split_time_s) << " s with";
    o << gain_fit_line;
    if (gain_effects.empty()) o << " no effect (none named, or none determined by the window)";
    o << "\n";
  }
  for (const auto& u : unexplained) o << "  unexplained: " << u << "\n";
  return o.str();
}

}  // namespace rnav
