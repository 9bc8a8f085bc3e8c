#include "scripts/compose/scenario/uav_scenario.hpp"

#include "common/io/options_io.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rnav {

namespace options_io {  // found by read_scenario's ADL

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
  check_tma(sc.tma);
  check_target(sc.target);
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

void UavScenario::print(std::ostream& os) const {
  print_scenario(*this, os, [this](nlohmann::json& j) {
    j["kind"] = "uav";
    j["origin"] = {{"lat_deg", origin.lat_deg}, {"lon_deg", origin.lon_deg}, {"h_m", origin.h_m}};
    j["duration_s"] = duration_s;
  });
}

std::string UavScenario::json_text() const {
  std::ostringstream os;
  print(os);
  return os.str();
}

}  // namespace rnav
