#include "uav_scenario.hpp"

#include "options_io.hpp"

#include <algorithm>
#include <cmath>

namespace rnav {

namespace options_io {

template <class V> void visit(TargetOptions& o, V& v) {
  v.num("start_north_m", o.start_north_m, -1e5, 1e5);
  v.num("start_east_m", o.start_east_m, -1e5, 1e5);
  v.num("speed_mps", o.speed_mps, 0, 30);
  v.num("heading_deg", o.heading_deg, -360, 360);
  v.quads("manoeuvres", o.manoeuvres);
}
template <class V> void visit(ObserverOptions& o, V& v) {
  v.choice("path", o.path, {"circle", "straight"});
  v.num("radius_m", o.radius_m, 20, 20000);
  v.num("speed_mps", o.speed_mps, 1, 200);
  v.num("altitude_m", o.altitude_m, 0, 5000);
  v.choice("direction", o.direction, {"ccw", "cw"});
  v.num("centre_offset_north_m", o.centre_offset_north_m, -1e5, 1e5);
  v.num("centre_offset_east_m", o.centre_offset_east_m, -1e5, 1e5);
  v.num("start_angle_deg", o.start_angle_deg, -360, 360);
  v.num("straight_heading_deg", o.straight_heading_deg, -360, 360);
  v.choice("guidance", o.guidance, {"orbit", "los", "estimate"});
  v.num("max_bank_deg", o.max_bank_deg, 1e-3, 80);
  v.num("max_turn_rate_dps", o.max_turn_rate_dps, 1e-3, 180);
  v.num("heading_time_constant_s", o.heading_time_constant_s, 0.1, 100);
  v.num("standoff_gain", o.standoff_gain, 0, 10);
  v.num("wind_north_mps", o.wind_north_mps, -100, 100);
  v.num("wind_east_mps", o.wind_east_mps, -100, 100);
  v.num("estimate_latency_s", o.estimate_latency_s, 0.01, 100);
  v.choice("guidance_estimator", o.guidance_estimator, TmaOptions::known_estimators());
}
template <class V> void visit(ObserverNavOptions& o, V& v) {
  v.num("white_sigma_m", o.white_sigma_m, 0, 100);
  v.num("corr_sigma_m", o.corr_sigma_m, 0, 100);
  v.num("corr_tau_s", o.corr_tau_s, 0.01, kInf);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 0, 10);
}
template <class V> void visit(SensorOptions& o, V& v) {
  v.num("sigma_deg", o.sigma_deg, 1e-4, 10);
  v.num("period_s", o.period_s, 0.01, 10);
  v.num("fov_centre_deg", o.fov_centre_deg, -180, 180);
  v.num("fov_half_deg", o.fov_half_deg, 0, 180);
  v.num("max_range_m", o.max_range_m, 1, 1e6);
  v.num("min_range_m", o.min_range_m, 0, 1e6);
}
template <class V> void visit(SensorEffectsOptions& o, V& v) {
  v.num("bearing_bias_rad", o.bearing_bias_rad, -0.2, 0.2);
  v.num("time_offset_s", o.time_offset_s, -10, 10);
  v.num("bias_drift_radps", o.bias_drift_radps, -0.01, 0.01);
  v.num("noise_scale", o.noise_scale, 1e-3, 100);
  v.num("correlated_noise_tau_s", o.correlated_noise_tau_s, 0, 1e5);
  v.num("outlier_prob", o.outlier_prob, 0, 0.5);
  v.num("outlier_scale", o.outlier_scale, 1, 1000);
  v.num("periodic_period_s", o.periodic_period_s, 0, 1e5);
  v.num("periodic_amplitude_rad", o.periodic_amplitude_rad, -0.2, 0.2);
}
template <class V> void visit(TmaOptions& o, V& v) {
  v.num("q_m2ps3", o.q_m2ps3, 0, 100);
  v.num("range_prior_m", o.range_prior_m, 1, 1e6);
  v.num("range_sigma_m", o.range_sigma_m, 1, 1e6);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 1e-3, 100);
  v.integer("bank_size", o.bank_size, 2, 64);
  v.num("bank_min_m", o.bank_min_m, 1, 1e6);
  v.num("bank_max_m", o.bank_max_m, 1, 1e6);
  v.flag("add_nav_noise", o.add_nav_noise);
  v.integer("pf_particles", o.pf_particles, 100, 1000000);
  v.choices("estimators", o.estimators, TmaOptions::known_estimators());
}
template <class V> void visit(UavLoggerOptions& o, V& v) {
  v.num("eval_time_s", o.eval_time_s, -1, 1e6);
  v.num("diverge_pos_m", o.diverge_pos_m, 0.01, 1e6);
  v.num("realizations_step_s", o.realizations_step_s, 0, 1e6);
  v.integer("track_realization", o.track_realization, -1, 999999999);
}

template <class F> void for_each_section(UavScenario& sc, F&& f) {
  f("target", sc.target);
  f("uav", sc.uav);
  f("uav_nav", sc.uav_nav);
  f("sensor", sc.sensor);
  f("sensor_effects", sc.sensor_effects);
  f("tma", sc.tma);
  f("logger", sc.logger);
  f("runner", sc.runner);
}

}  // namespace options_io
using namespace options_io;

UavScenario UavScenario::from_json(const nlohmann::json& doc) {
  UavScenario sc;
  sc.runner.window_s = 20;  // keeps every batch of estimates well under LCM's 64 KB datagram
  read_scenario(doc, "uav", sc, [&](Section& root) {
    Section o = root.section("origin");
    sc.origin.lat_deg = o.number("lat_deg", sc.origin.lat_deg, -89, 89);
    sc.origin.lon_deg = o.number("lon_deg", sc.origin.lon_deg, -180, 180);
    sc.origin.h_m = o.number("h_m", sc.origin.h_m, -500, 9000);
    o.finish();
    sc.duration_s = root.number("duration_s", sc.duration_s, -1, 1e6);
  });

  if (sc.duration_s != -1 && sc.duration_s <= 0)
    throw ConfigError("scenario key 'duration_s' must be > 0 (or -1: two orbits)");
  if (sc.closed_loop()) {
    // The guidance at time t uses the estimate of t - estimate_latency_s, which a lock-step window
    // of at most that length has received (it was published in an earlier window): the loop is
    // causal and its results do not depend on the window (batch) size.
    require_multiple(sc.uav.estimate_latency_s, sc.sensor.period_s, "uav.estimate_latency_s", "sensor.period_s");
    const bool window_given = doc.is_object() && doc.contains("runner") && doc["runner"].is_object() &&
                              doc["runner"].contains("window_s");
    if (!window_given) sc.runner.window_s = std::min(sc.runner.window_s, sc.uav.estimate_latency_s);
    if (sc.runner.window_s > sc.uav.estimate_latency_s + 1e-9)
      throw ConfigError("scenario key 'runner.window_s' = " + std::to_string(sc.runner.window_s) +
                        " s exceeds uav.estimate_latency_s = " + std::to_string(sc.uav.estimate_latency_s) +
                        " s: with uav.guidance = \"" + sc.uav.guidance +
                        "\" a window must not be longer than the estimate's age (set runner.window_s <= it, or leave it out)");
    if (sc.uav.path != "circle")
      throw ConfigError("scenario key 'uav.path' = \"" + sc.uav.path + "\" applies only to uav.guidance = \"orbit\"");
    if (std::hypot(sc.uav.wind_north_mps, sc.uav.wind_east_mps) >= sc.uav.speed_mps)
      throw ConfigError("scenario keys 'uav.wind_north_mps', 'uav.wind_east_mps': the wind speed must be below the airspeed uav.speed_mps");
  }
  if (!(sc.runner.window_s > 0))
    throw ConfigError("scenario key 'runner.window_s' must be > 0 in the UAV scenario (0, the whole realization as one "
                      "window, is for the landing scenario: the UAV's guidance feeds estimates back between windows)");
  require_multiple(sc.runner.window_s, sc.sensor.period_s, "runner.window_s", "sensor.period_s");
  if (sc.closed_loop() && std::find(sc.tma.estimators.begin(), sc.tma.estimators.end(), sc.uav.guidance_estimator) ==
                              sc.tma.estimators.end())
    throw ConfigError("scenario key 'uav.guidance_estimator' = \"" + sc.uav.guidance_estimator +
                      "\" is not among tma.estimators: guidance would get no estimate (add it to tma.estimators)");
  if (sc.tma.bank_min_m >= sc.tma.bank_max_m)
    throw ConfigError("scenario key 'tma.bank_min_m' must be below tma.bank_max_m");
  for (const auto& m : sc.target.manoeuvres)
    if (m[0] < 0 || m[1] <= 0)
      throw ConfigError("scenario key 'target.manoeuvres': each needs t_s >= 0 and duration_s > 0");
  if (sc.logger.eval_time_s > sc.duration_s && sc.duration_s > 0)
    throw ConfigError("scenario key 'logger.eval_time_s' lies after duration_s");
  if (sc.runner.flush_s < sc.sensor.period_s)
    throw ConfigError("scenario key 'runner.flush_s' must be at least sensor.period_s");
  if (sc.duration_s < 0) sc.duration_s = 2 * sc.orbit_period_s();
  if (sc.logger.eval_time_s < 0) sc.logger.eval_time_s = std::min(2 * sc.orbit_period_s(), sc.duration_s);
  return sc;
}

UavScenario UavScenario::load(const std::string& file, const std::vector<std::string>& overrides) {
  return load_scenario<UavScenario>(file, overrides);
}

void check_track_realization(const UavLoggerOptions& o, long n_realizations) {
  if (o.track_realization >= n_realizations)
    throw ConfigError("scenario key 'logger.track_realization' = " + std::to_string(o.track_realization) +
                      " names no realization of this run (0 ... " + std::to_string(n_realizations - 1) +
                      "; -1: no track.csv)");
}

const std::vector<std::string>& TmaOptions::known_estimators() {
  static const std::vector<std::string> names{"ekf", "rpekf", "ml", "pf"};
  return names;
}

double UavScenario::orbit_period_s() const { return 2 * M_PI * uav.radius_m / uav.speed_mps; }

double UavScenario::eval_time_s() const { return logger.eval_time_s; }

void UavScenario::print(std::ostream& os) const {
  print_scenario(*this, os, [this](nlohmann::json& j) {
    j["kind"] = "uav";
    j["origin"] = {{"lat_deg", origin.lat_deg}, {"lon_deg", origin.lon_deg}, {"h_m", origin.h_m}};
    j["duration_s"] = duration_s;
  });
}

}  // namespace rnav
