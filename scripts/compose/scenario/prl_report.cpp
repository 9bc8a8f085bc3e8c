#include "scripts/compose/scenario/prl_report.hpp"

#include "common/io/config.hpp"

#include <cmath>
#include <map>
#include <vector>

namespace rnav {

namespace {

std::vector<double> values(const nlohmann::json& x, const char* key, const std::string& where) {
  const auto it = x.find(key);
  if (it == x.end() || it->is_null()) return {};
  std::vector<double> v;
  if (it->is_number()) {
    v.push_back(it->get<double>());
  } else if (it->is_array()) {
    for (const auto& e : *it) {
      if (!e.is_number()) throw ConfigError(where + ": '" + key + "' holds a value that is not a number");
      v.push_back(e.get<double>());
    }
  } else {
    throw ConfigError(where + ": '" + key + "' is neither a number nor a list");
  }
  for (double d : v)
    if (!std::isfinite(d)) throw ConfigError(where + ": '" + key + "' holds a value that is not finite");
  return v;
}

// A noise finding named on all three channels with values within 3 SE of their mean: the mean.
struct NoiseFinding {
  std::map<std::string, std::pair<double, double>> by_channel;  // channel -> (value, se)
};

double common_value(const NoiseFinding& f, const std::string& name, const std::string& source) {
  static const char* const kChannels[] = {"range", "course", "glide"};
  std::string missing;
  for (const char* c : kChannels)
    if (!f.by_channel.count(c)) missing += std::string(missing.empty() ? "" : ", ") + c;
  if (!missing.empty())
    throw ConfigError(source + ": " + name + " is not named on " + missing +
                      ": the landing radar simulation's fluctuation noise is one model for all three channels");
  double m = 0;
  for (const auto& [c, v] : f.by_channel) m += v.first;
  m /= 3;
  for (const auto& [c, v] : f.by_channel)
    if (std::isfinite(v.second) && v.second > 0 && std::abs(v.first - m) > 3 * v.second)
      throw ConfigError(source + ": " + name + " differs between the channels (" + c + ": " + std::to_string(v.first) +
                        ", their mean " + std::to_string(m) +
                        "): the landing radar simulation's fluctuation noise is one model for all three channels");
  return m;
}

// The prl_effects key of a per-channel effect's parameter (bias_drift, bias_step, periodic: one
// entry per channel, its parameter naming the channel); a ConfigError at `where` for another.
double PrlEffectsOptions::*channel_key(const std::string& effect, const std::string& param, const std::string& where) {
  using K = double PrlEffectsOptions::*;
  static const std::map<std::pair<std::string, std::string>, K> kKey = {
      {{"bias_drift", "range_mps"}, &PrlEffectsOptions::drift_range_mps},
      {{"bias_drift", "course_radps"}, &PrlEffectsOptions::drift_course_radps},
      {{"bias_drift", "glide_radps"}, &PrlEffectsOptions::drift_glide_radps},
      {{"bias_step", "range_m"}, &PrlEffectsOptions::step_range_m},
      {{"bias_step", "course_rad"}, &PrlEffectsOptions::step_course_rad},
      {{"bias_step", "glide_rad"}, &PrlEffectsOptions::step_glide_rad},
      {{"periodic", "sin_range_m"}, &PrlEffectsOptions::periodic_range_m},
      {{"periodic", "sin_course_rad"}, &PrlEffectsOptions::periodic_course_rad},
      {{"periodic", "sin_glide_rad"}, &PrlEffectsOptions::periodic_glide_rad}};
  const auto it = kKey.find({effect, param});
  if (it == kKey.end()) throw ConfigError(where + ": unknown parameter '" + param + "'");
  return it->second;
}

}  // namespace

PrlEffectsOptions prl_effects_from_report(const nlohmann::json& j, const std::string& source) {
  if (!j.is_object() || !j.contains("effects") || !j["effects"].is_array())
    throw ConfigError(source + ": not a diagnosis report (no \"effects\" list)");
  if (j.value("kind", std::string()) != "prl")
    throw ConfigError(source + ": not a landing-radar diagnosis report (its \"kind\" is \"" + j.value("kind", std::string()) +
                      "\", not \"prl\")");
  PrlEffectsOptions fx;
  NoiseFinding scale, out, corr;
  bool stepped = false;
  const auto& effects = j["effects"];
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const auto& x = effects[i];
    if (x.value("nominal", false)) continue;  // the paper's constant biases: the scenario's own (prl.bias_*)
    const std::string name = x.value("name", std::string());
    const std::string where = source + ": effects[" + std::to_string(i) + "] " + name;
    const std::vector<double> est = values(x, "estimate", where), se = values(x, "stderr", where);
    std::vector<std::string> params;
    if (x.contains("params") && x["params"].is_array())
      for (const auto& p : x["params"]) params.push_back(p.get<std::string>());
    auto need = [&](std::size_t n) {
      if (est.size() != n) throw ConfigError(where + ": " + std::to_string(est.size()) + " estimate(s), expected " + std::to_string(n));
    };
    auto param = [&](std::size_t k) { return k < params.size() ? params[k] : std::string(); };
    const double scanned = x.contains("scanned") ? x["scanned"].value("value", NAN) : NAN;
    if (name == "range_gain") {
      need(1), fx.range_gain = est[0];
    } else if (name == "time_offset") {
      need(1), fx.time_offset_s = est[0];
    } else if (name == "elevation_refraction") {
      need(1), fx.elevation_refraction_rad = est[0];
    } else if (name == "azimuth_elevation_coupling") {
      need(1), fx.azimuth_elevation_coupling_rad = est[0];
    } else if (name == "site_offset") {
      need(3), fx.site_offset_east_m = est[0], fx.site_offset_north_m = est[1], fx.site_offset_up_m = est[2];
    } else if (name == "bias_drift") {
      need(1), fx.*channel_key(name, param(0), where) = est[0];
    } else if (name == "bias_step") {
      need(1);
      if (!std::isfinite(scanned)) throw ConfigError(where + ": no step time (scanned.value)");
      if (stepped && scanned != fx.step_time_s)
        throw ConfigError(where + ": a step at " + std::to_string(scanned) + " s beside one at " + std::to_string(fx.step_time_s) +
                          " s: the landing radar simulation has one step time (prl_effects.step_time_s)");
      fx.step_time_s = scanned, stepped = true;
      fx.*channel_key(name, param(0), where) = est[0];
    } else if (name == "periodic") {
      need(2);
      if (!std::isfinite(scanned)) throw ConfigError(where + ": no period (scanned.value)");
      const double se_cos = se.size() == 2 ? se[1] : 0;
      if (std::abs(est[1]) > 2 * se_cos)
        throw ConfigError(where + ": its cos term " + std::to_string(est[1]) +
                          " is not 0 within 2 SE: the landing radar simulation's oscillation has phase 0 (prl_effects.periodic_*)");
      if (fx.periodic_period_s > 0 && fx.periodic_period_s != scanned)
        throw ConfigError(where + ": a second period: the landing radar simulation has one (prl_effects.periodic_period_s)");
      fx.periodic_period_s = scanned;
      fx.*channel_key(name, param(0), where) = est[0];
    } else if (name == "noise_scale" || name == "outliers" || name == "correlated_noise") {
      const std::string ch = x.value("channel", std::string());
      const double s = se.empty() ? NAN : se[0];
      if (name == "noise_scale") scale.by_channel[ch] = {est.at(0), s};
      if (name == "outliers") out.by_channel[ch] = {est.at(0), s};
      if (name == "correlated_noise") {
        if (est.size() < 2 || est[1] <= 0.95)
          throw ConfigError(where + ": a correlated share of " + (est.size() < 2 ? std::string("?") : std::to_string(est[1])) +
                            ": the landing radar simulation's correlated noise is wholly correlated (share above 0.95)");
        corr.by_channel[ch] = {est[0], s};
      }
    } else {
      throw ConfigError(where + ": an effect the landing radar simulation cannot make");
    }
  }
  if (!scale.by_channel.empty()) fx.noise_scale = common_value(scale, "noise_scale", source);
  if (!out.by_channel.empty()) fx.outlier_prob = common_value(out, "outliers", source);
  if (!corr.by_channel.empty()) fx.correlated_noise_tau_s = common_value(corr, "correlated_noise", source);
  return fx;
}

}  // namespace rnav
