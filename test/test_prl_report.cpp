// A landing-radar diagnosis report as the landing radar's errors (scripts/compose/scenario/
// prl_report.hpp, scenario key prl_effects_report): each named entry lands on its prl_effects
// key; what the simulation cannot make (a phase, two step times, noise on one channel only,
// another report kind) is refused naming it; the scenario takes the report and refuses it beside
// explicit prl_effects keys; the printed scenario holds the values.
#include "common/io/config.hpp"
#include "scripts/compose/scenario/prl_report.hpp"
#include "scripts/compose/scenario/scenario.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace rnav;
using nlohmann::json;

namespace {

json effect(const std::string& name, const std::vector<std::string>& params, json estimate, json stderr_ = nullptr) {
  json e = {{"name", name}, {"params", params}, {"estimate", estimate}};
  if (!stderr_.is_null()) e["stderr"] = stderr_;
  return e;
}

json report(json effects) { return {{"kind", "prl"}, {"effects", effects}}; }

}  // namespace

TEST_CASE("prl report: each named effect lands on its prl_effects key") {
  json fx = json::array();
  fx.push_back({{"name", "range_bias"}, {"params", {"m"}}, {"estimate", 34.0}, {"nominal", true}});  // the scenario's own
  fx.push_back(effect("range_gain", {"g"}, 0.002));
  fx.push_back(effect("time_offset", {"tau_s"}, 0.3));
  fx.push_back(effect("site_offset", {"east_m", "north_m", "up_m"}, {1.0, -2.0, 0.5}));
  fx.push_back(effect("bias_drift", {"glide_radps"}, 1e-6));
  json step = effect("bias_step", {"course_rad"}, 0.002);
  step["scanned"] = {{"param", "t_s"}, {"value", 250.0}};
  fx.push_back(step);
  json per = effect("periodic", {"sin_range_m", "cos_range_m"}, {3.0, 0.1}, {0.2, 0.2});
  per["scanned"] = {{"param", "period_s"}, {"value", 40.0}};
  fx.push_back(per);
  for (const char* ch : {"range", "course", "glide"}) {
    json n = effect("noise_scale", {"ratio"}, 1.5, 0.05);
    n["channel"] = ch;
    fx.push_back(n);
  }
  const PrlEffectsOptions o = prl_effects_from_report(report(fx), "r.json");
  CHECK(o.range_gain == 0.002);
  CHECK(o.time_offset_s == 0.3);
  CHECK(o.site_offset_north_m == -2.0);
  CHECK(o.drift_glide_radps == 1e-6);
  CHECK(o.step_time_s == 250.0);
  CHECK(o.step_course_rad == 0.002);
  CHECK(o.periodic_period_s == 40.0);
  CHECK(o.periodic_range_m == 3.0);
  CHECK(o.noise_scale == Approx(1.5));
}

TEST_CASE("prl report: what the simulation cannot make is refused, naming it") {
  json per = effect("periodic", {"sin_range_m", "cos_range_m"}, {3.0, 2.0}, {0.2, 0.2});
  per["scanned"] = {{"param", "period_s"}, {"value", 40.0}};
  CHECK_THROWS_WITH(prl_effects_from_report(report({per}), "r.json"), Catch::Contains("effects[0] periodic") && Catch::Contains("phase 0"));
  json s1 = effect("bias_step", {"range_m"}, 5.0), s2 = effect("bias_step", {"glide_rad"}, 0.001);
  s1["scanned"] = {{"value", 100.0}};
  s2["scanned"] = {{"value", 300.0}};
  CHECK_THROWS_WITH(prl_effects_from_report(report({s1, s2}), "r.json"), Catch::Contains("one step time"));
  json n = effect("noise_scale", {"ratio"}, 2.0, 0.1);
  n["channel"] = "course";
  CHECK_THROWS_WITH(prl_effects_from_report(report({n}), "r.json"), Catch::Contains("not named on range, glide"));
  CHECK_THROWS_WITH(prl_effects_from_report(report({effect("warp_drive", {"x"}, 1.0)}), "r.json"),
                    Catch::Contains("warp_drive") && Catch::Contains("cannot make"));
  CHECK_THROWS_WITH(prl_effects_from_report({{"kind", "multi"}, {"effects", json::array()}}, "r.json"),
                    Catch::Contains("not a landing-radar diagnosis report"));
}

TEST_CASE("prl report: the scenario takes it, refuses it beside prl_effects keys, and prints the values") {
  const auto dir = std::filesystem::temp_directory_path() / "rnav_test_prl_report";
  std::filesystem::create_directories(dir);
  const std::string rep = (dir / "report.json").string();
  std::ofstream(rep) << report({effect("range_gain", {"g"}, 0.004)}).dump();
  const std::string paper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";
  const Scenario sc = Scenario::load(paper, {"prl_effects_report=" + rep});
  CHECK(sc.prl_effects.range_gain == 0.004);
  CHECK(sc.prl_effects_report.empty());
  CHECK(sc.json_text().find("prl_effects_report") == std::string::npos);
  CHECK(json::parse(sc.json_text())["prl_effects"]["range_gain"] == 0.004);
  CHECK_THROWS_WITH(Scenario::load(paper, {"prl_effects_report=" + rep, "prl_effects.time_offset_s=0.1"}),
                    Catch::Contains("given together"));
  CHECK_THROWS_WITH(Scenario::load(paper, {"prl_effects_report=" + (dir / "missing.json").string()}), Catch::Contains("cannot read"));
  std::filesystem::remove_all(dir);
}
