#include "scripts/compose/scene/scene_effects_json.hpp"

#include "common/io/config.hpp"
#include "common/physics/multi_effect_columns.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace rnav {

namespace {

const std::set<std::string>& not_columns() {
  static const std::set<std::string> s{"noise_scale", "correlated_noise", "outliers", "target_maneuver"};
  return s;
}

std::string text_or_empty(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() || it->is_null() ? std::string() : it->get<std::string>();
}

double number_at(const nlohmann::json& j, const char* key, const std::string& where, double fallback, bool required) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) {
    if (required) throw ConfigError(where + ": '" + key + "' is missing");
    return fallback;
  }
  if (!it->is_number() || !std::isfinite(it->get<double>())) throw ConfigError(where + ": '" + key + "' is not a finite number");
  return it->get<double>();
}

}  // namespace

scene::SceneErrors nominal_errors(double sb, double sr) {
  scene::SceneErrors e;
  e.nominal_bearing_sigma_rad = sb;
  e.nominal_range_sigma_m = sr;
  return e;
}

scene::SceneErrors errors_from_report(const nlohmann::json& j, const std::string& source, const std::string& recording, double sb,
                                      double sr, bool use_simulated) {
  if (!j.is_object() || text_or_empty(j, "kind") != "multi")
    throw ConfigError(source + ": not a multi-sensor diagnosis report (its \"kind\" is not \"multi\")");
  scene::SceneErrors e = nominal_errors(sb, sr);
  const auto& known = multi_effect::names();
  const auto effects = j.find("effects");
  if (effects == j.end() || !effects->is_array()) throw ConfigError(source + ": no \"effects\" list");
  for (std::size_t i = 0; i < effects->size(); ++i) {
    const auto& x = (*effects)[i];
    const std::string where = source + ": effects[" + std::to_string(i) + "]";
    const std::string name = text_or_empty(x, "name");
    if (not_columns().count(name)) continue;
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw ConfigError(where + ": effect '" + name + "' is not one the simulation can make");
    const auto& sc = x.contains("scope") ? x["scope"] : nlohmann::json::object();
    const std::string rec = text_or_empty(sc, "recording");
    if (!rec.empty() && rec != recording) continue;  // another recording's own
    scene::InjectedEffect ie;
    ie.name = name;
    ie.sensor = text_or_empty(sc, "sensor");
    ie.target = text_or_empty(sc, "target");
    const auto est = x.find("estimate");
    if (est == x.end()) throw ConfigError(where + ": no estimate");
    if (est->is_number()) {
      ie.theta = {est->get<double>()};
    } else if (est->is_array()) {
      for (const auto& v : *est) {
        if (!v.is_number()) throw ConfigError(where + ": estimate holds a value that is not a number");
        ie.theta.push_back(v.get<double>());
      }
    } else {
      throw ConfigError(where + ": estimate is neither a number nor a list");
    }
    if (x.contains("scanned")) ie.scan_value = number_at(x["scanned"], "value", where + ".scanned", 0, true);
    e.effects.push_back(ie);
  }
  // noise: this recording's channels ("REC/sensor:target:q" pooled, "sensor:target:q" alone)
  const auto noise = j.find("noise");
  bool any_b = false, any_r = false;
  if (noise != j.end() && noise->is_object()) {
    bool pooled = false;  // a pooled report's channels are "REC/sensor:target:quantity"
    for (const auto& kv : noise->items()) pooled = pooled || kv.key().find('/') != std::string::npos;
    bool found = false;
    for (const auto& kv : noise->items()) {
      std::string ch = kv.key();
      if (pooled) {
        const auto slash = ch.find('/');
        if (slash == std::string::npos || ch.substr(0, slash) != recording) continue;
        ch = ch.substr(slash + 1);
      }
      found = true;
      const auto& n = kv.value();
      const std::string where = source + ": noise \"" + kv.key() + "\"";
      const bool is_range = ch.size() > 6 && ch.compare(ch.size() - 6, 6, ":range") == 0;
      NoiseParams p;
      const double sigma = number_at(n, "sigma", where, 0, true);
      p.s2 = sigma * sigma;
      p.lambda = number_at(n, "correlated_share", where, 0, false);
      p.tau_s = number_at(n, "tau_s", where, 1, false);
      p.p_out = number_at(n, "outlier_fraction", where, 0, false);
      const double so = number_at(n, "outlier_sd", where, NAN, p.p_out > 0);
      p.s_out2 = std::isfinite(so) ? so * so : 0;
      // the noise the report says a simulation draws, where it says (its "simulated" model:
      // the identified noise with the slow wander no named effect explains)
      if (use_simulated && n.contains("simulated") && n["simulated"].is_object()) {
        const auto& m = n["simulated"];
        const std::string mw = where + ".simulated";
        const double ms = number_at(m, "sigma", mw, 0, true);
        p.s2 = ms * ms;
        p.lambda = number_at(m, "correlated_share", mw, 0, false);
        p.tau_s = number_at(m, "tau_s", mw, 1, false);
      }
      p.nom_share = number_at(n, "nominal_share", where, 0, false);
      p.nom_tau_s = number_at(n, "nominal_correlated_tau_s", where, 1, false);
      try {
        check_noise_params(p);
      } catch (const std::invalid_argument& x) {
        throw ConfigError(where + ": " + x.what());
      }
      e.noise[ch] = p;
      // the nominal sigma of its quantity: sigma / noise_scale
      const double scale = number_at(n, "noise_scale", where, NAN, false);
      if (std::isfinite(scale) && scale > 0) {
        if (is_range && !any_r) e.nominal_range_sigma_m = sigma / scale, any_r = true;
        if (!is_range && !any_b) e.nominal_bearing_sigma_rad = sigma / scale, any_b = true;
      }
    }
    if (pooled && !found) throw ConfigError(source + ": the pooled report holds no channel of recording '" + recording + "'");
  }
  // the targets' offsets no named effect explains: this recording's groups ("REC/sensor:quantity"
  // pooled, "sensor:quantity" alone), drawn with the simulated noise (identified about each
  // channel's mean), not with the identified one
  const auto offsets = j.find("offsets");
  if (use_simulated && offsets != j.end() && offsets->is_object()) {
    for (const auto& kv : offsets->items()) {
      std::string key = kv.key();
      const auto slash = key.find('/');
      if (slash != std::string::npos) {
        if (key.substr(0, slash) != recording) continue;
        key = key.substr(slash + 1);
      }
      const std::string where = source + ": offsets \"" + kv.key() + "\"";
      scene::TargetOffsets to;
      to.mean = number_at(kv.value(), "mean", where, 0, true);
      to.sd = number_at(kv.value(), "sd", where, 0, true);
      if (kv.value().contains("explained")) {
        if (!kv.value()["explained"].is_array()) throw ConfigError(where + ": 'explained' is not a list");
        for (const auto& c : kv.value()["explained"]) {
          if (!c.is_string()) throw ConfigError(where + ": 'explained' holds a value that is not a channel name");
          std::string ch = c.get<std::string>();
          const auto cs = ch.find('/');
          if (cs != std::string::npos) ch = ch.substr(cs + 1);
          to.explained.insert(ch);
        }
      }
      e.offsets[key] = to;
    }
  }
  try {
    e.check();
  } catch (const std::invalid_argument& x) {
    throw ConfigError(source + ": " + x.what());
  }
  return e;
}

}  // namespace rnav
