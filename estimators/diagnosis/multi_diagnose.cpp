#include "multi_diagnose.hpp"

#include "atomic_file.hpp"

#include "config.hpp"
#include "diagnose_report.hpp"
#include "multi_problem.hpp"
#include "search_json.hpp"
#include "stats.hpp"
#include "target_model.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rnav {

MultiReport diagnose_multi(const MultiSensorData& data, const MultiDiagnoseOptions& o) {
  if (!(o.sigma_bearing_deg > 0) || !(o.sigma_range_m > 0)) throw ConfigError("multi diagnosis: nominal sigmas must be > 0");
  MultiReport rep;
  const std::vector<AssociatedDetection> a = associate(data, o.association, rep.association);
  MultiProblem mp = build_multi_problem(a, o.sigma_bearing_deg * kDegToRad, o.sigma_range_m, o.split_fraction, o.step_grid);
  rep.split_time_s = mp.split_time_s;
  rep.dropped_channels = mp.dropped_channels;
  check_limit_entries(mp.problem, o.search.injection, "diagnose multi");
  rep.result = search_effects(mp.problem, o.search);
  const SearchResult& r = rep.result;

  // gain per sensor:target: compensated measurement against the held-out reference
  std::map<std::string, std::pair<double, double>> sums;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].t_s < mp.split_time_s) continue;
    const long ib = mp.bearing_obs[i], ir = mp.range_obs[i];
    if (ib < 0) continue;
    const std::string key = a[i].sensor + ":" + a[i].target;
    MultiGain& g = rep.gain[key];
    const auto yb = mp.problem.y[static_cast<std::size_t>(ib)];
    const double eb0 = yb - r.nominal_oos(ib), eb1 = yb - r.extended_oos(ib);
    double e0, e1;
    if (a[i].has_range && ir >= 0) {
      const auto yr = mp.problem.y[static_cast<std::size_t>(ir)];
      const double er0 = yr - r.nominal_oos(ir), er1 = yr - r.extended_oos(ir), R = a[i].range_m;
      // position error: radial and cross-range components
      e0 = std::hypot(er0, R * eb0);
      e1 = std::hypot(er1, R * eb1);
      g.unit = "m";
    } else {
      e0 = eb0 / kDegToRad;
      e1 = eb1 / kDegToRad;
      g.unit = "deg";
    }
    sums[key].first += e0 * e0;
    sums[key].second += e1 * e1;
    ++g.n;
  }
  for (auto& [k, g] : rep.gain) {
    g.nominal_rms = std::sqrt(sums[k].first / std::max(1, g.n));
    g.extended_rms = std::sqrt(sums[k].second / std::max(1, g.n));
  }
  if (o.test_target_model) {
    TargetModelOptions to;
    to.search = o.search;
    to.threads = o.search.injection.threads;
    const TargetModelResult tm = test_target_model(data.truth_on_level(), LocalLevelFrame(data.observer.front().g, 0.0), to);
    rep.target_effects = tm.maneuvers;
    rep.target_notes = tm.notes;
  }
  rep.problem = std::move(mp.problem);
  return rep;
}

nlohmann::ordered_json MultiReport::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = "multi";
  j["association"] = nlohmann::ordered_json::object();
  for (const auto& [s, st] : association)
    j["association"][s] = {{"scans", st.scans}, {"detections", st.detections}, {"ambiguous_scans", st.ambiguous_scans},
                           {"associated", st.associated}, {"missed", st.missed}};
  j["dropped_channels"] = dropped_channels;
  const nlohmann::ordered_json core = search_json(problem, result);
  j["effects"] = core["effects"];
  for (const auto& e : target_effects) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    x["scope"] = scope_json(e.scope);
    x["params"] = {"t_s", e.params[0], e.params[1]};
    x["estimate"] = {e.scan_value, e.estimate[0], e.estimate[1]};
    x["stderr"] = {e.scan_se, e.stderr_[0], e.stderr_[1]};
    x["evidence"] = evidence_json(e);
    x["confounded_with"] = nlohmann::ordered_json::array();
    x["note"] = "the reference track departs from constant velocity here (tested on the track itself)";
    j["effects"].push_back(x);
  }
  j["gain"] = nlohmann::ordered_json::object();
  for (const auto& [k, g] : gain)
    j["gain"][k] = {{"n", g.n}, {"nominal_rms", g.nominal_rms}, {"extended_rms", g.extended_rms}, {"unit", g.unit}};
  j["gain_window"] = "fit on t < " + short_num(split_time_s) + " s, scored on t >= " + short_num(split_time_s) + " s";
  j["gain_effects"] = result.holdout_effects;
  for (const char* k : {"noise", "series_gain", "gain_fit", "limits_method", "detection_limits", "naming_limits", "fisher_limits", "injected_limits", "separation_limits", "scope_support", "unexplained", "familywise"}) j[k] = core[k];
  j["target_model"] = target_notes;
  return j;
}

std::string MultiReport::text() const {
  std::ostringstream o;
  for (const auto& [s, st] : association) {
    o << "  sensor " << s << ": " << st.scans << " scans, " << st.detections << " detections, associated";
    for (const auto& [t, n] : st.associated) o << " " << t << ":" << n;
    o << " (ambiguous scans " << st.ambiguous_scans << ")\n";
  }
  for (const auto& d : dropped_channels) o << "  not diagnosed (fewer than 10 associated detections): " << d << "\n";
  o << search_text(problem, result);
  for (const auto& e : target_effects)
    o << "  EFFECT   target_maneuver [target " << e.scope.target << "]: at t = " << short_num(e.scan_value) << " +- "
      << short_num(e.scan_se) << " s, dv = (" << short_num(e.estimate[0]) << " +- " << short_num(e.stderr_[0]) << ", "
      << short_num(e.estimate[1]) << " +- " << short_num(e.stderr_[1]) << ") m/s\n";
  for (const auto& n : target_notes) o << "  target   " << n << "\n";
  for (const auto& [k, g] : gain)
    o << "  gain " << k << ": RMS " << short_num(g.nominal_rms) << " -> " << short_num(g.extended_rms) << " " << g.unit
      << " (n " << g.n << ")\n";
  o << "  gain window: fit on t < " << short_num(split_time_s) << " s with";
  o << gain_fit_text(problem, result);
  if (result.holdout_effects.empty()) o << " no effect (none named, or none determined by the window)";
  o << "\n";
  return o.str();
}

void MultiReport::write_residuals_csv(const std::string& file) const {
  std::ostringstream f;
  f << "t_s,sensor,target,quantity,residual,extended_fit,estimation,outlier\n";
  std::vector<std::size_t> pos(problem.channels.size(), 0);
  char b[256];
  for (std::size_t i = 0; i < problem.size(); ++i) {
    const auto c = static_cast<std::size_t>(problem.channel[i]);
    const Channel& ch = problem.channels[c];
    const auto& flags = result.noise[c].fit.outlier;
    const bool out = pos[c] < flags.size() && flags[pos[c]];
    ++pos[c];
    std::snprintf(b, sizeof b, "%.6f,%s,%s,%s,%.9g,%.9g,%d,%d\n", problem.t_s[i], ch.sensor.c_str(), ch.target.c_str(),
                  ch.unit == "m" ? "range" : "bearing", problem.y[i], result.effect_fit(static_cast<Eigen::Index>(i)),
                  problem.estimation[i] ? 1 : 0, out ? 1 : 0);
    f << b;
  }
  if (!f.flush()) throw ConfigError("cannot write " + file + " (disk full?)");
  write_file_atomic(file, f.str());
}

}  // namespace rnav
