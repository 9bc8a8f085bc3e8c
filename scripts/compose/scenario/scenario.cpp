#include "scripts/compose/scenario/scenario.hpp"

#include "common/io/options_io.hpp"
#include "scripts/compose/scenario/prl_report.hpp"
#include "scripts/compose/scenario/scenario_paths.hpp"

#include <fstream>

#include <filesystem>
#include <sstream>

namespace rnav {

namespace options_io {  // found by read_scenario's ADL

// Every section of a scenario, in file order.
template <class F> void for_each_section(Scenario& sc, F&& f) {
  f("runway", sc.runway);
  f("radar", sc.radar);
  f("trajectory", sc.trajectory);
  f("prl", sc.prl);
  f("prl_effects", sc.prl_effects);
  f("snsins", sc.snsins);
  f("datalink", sc.datalink);
  f("prl_bias", sc.prl_bias);
  f("logger", sc.logger);
  f("runner", sc.runner);
}

}  // namespace options_io
using namespace options_io;

Scenario Scenario::from_json(const nlohmann::json& doc) {
  Scenario sc;
  read_scenario(doc, "prl", sc, [&sc](Section& root) { sc.prl_effects_report = root.string("prl_effects_report", ""); });

  resolve_azimuth_reference(sc.runway, sc.radar);
  const double step = sc.trajectory.step_s;
  require_multiple(sc.prl.period_s, step, "prl.period_s");
  require_multiple(sc.prl.phase_s, step, "prl.phase_s");
  require_multiple(sc.snsins.link_period_s, step, "snsins.link_period_s");
  require_multiple(sc.snsins.link_phase_s, step, "snsins.link_phase_s");
  require_multiple(sc.runner.window_s, step, "runner.window_s");
  if (sc.runner.flush_s <= sc.prl_bias.nav_wait_s + sc.snsins.latency_s)
    throw ConfigError("scenario key 'runner.flush_s' must exceed prl_bias.nav_wait_s + "
                      "snsins.latency_s so every plot is decided before the realization ends");
  if (sc.trajectory.end_x_m >= sc.trajectory.intercept_x_m)
    throw ConfigError("scenario key 'trajectory.end_x_m' must be below trajectory.intercept_x_m");
  check_datalink(sc.datalink);
  // One message's air time must end before the next message is sent.
  const DatalinkOptions& d = sc.datalink;
  const double air_s = message_air_time_s(d);
  if (air_s > sc.snsins.link_period_s)
    throw ConfigError("scenario key 'datalink.message_bits': a message of " + std::to_string(d.message_bits) + " bits takes " +
                      value_text(air_s) + " s at datalink.chip_rate_hz / datalink.code_length, longer than "
                      "snsins.link_period_s = " + value_text(sc.snsins.link_period_s) + " s");
  check_logger(sc.logger);
  return sc;
}

Scenario Scenario::load(const std::string& file, const std::vector<std::string>& overrides) {
  Scenario sc = load_scenario<Scenario>(file, overrides);
  // trajectory.replay_csv and prl_effects_report: paths by the scenario rule (scenario_paths.hpp)
  sc.trajectory.replay_csv = resolve_scenario_path(sc.trajectory.replay_csv, "trajectory.replay_csv", file, overrides);
  // prl_effects_report: its effects replace prl_effects
  if (!sc.prl_effects_report.empty()) {
    const std::filesystem::path path = resolve_scenario_path(sc.prl_effects_report, "prl_effects_report", file, overrides);
    nlohmann::json given, nominal;
    PrlEffectsOptions defaults;
    write_section(given, "s", sc.prl_effects);
    write_section(nominal, "s", defaults);
    if (given != nominal)
      throw ConfigError("scenario key 'prl_effects_report' and keys of section 'prl_effects' given together: the report's "
                        "effects replace that section, give one of them");
    std::ifstream f(path);
    if (!f) throw ConfigError("scenario key 'prl_effects_report': cannot read " + path.string());
    nlohmann::json report;
    try {
      report = nlohmann::json::parse(f);
    } catch (const nlohmann::json::exception& e) {
      throw ConfigError("scenario key 'prl_effects_report': " + path.string() + " is not JSON (" + e.what() + ")");
    }
    sc.prl_effects = prl_effects_from_report(report, path.string());
    sc.prl_effects_report.clear();
  }
  return sc;
}

std::vector<std::string> Scenario::node_names() const {
  std::vector<std::string> n{"trajectory", "snsins"};
  if (datalink.enabled) n.push_back("datalink");
  for (const char* m : {"prl", "prl_bias", "logger"}) n.push_back(m);
  return n;
}

void Scenario::print(std::ostream& os) const {
  print_scenario(*this, os, [](nlohmann::json&) {});
}

std::string Scenario::json_text() const {
  std::ostringstream os;
  print(os);
  return os.str();
}

}  // namespace rnav
