// Unit tests of common/io/config.hpp and scripts/compose/scenario/scenario.hpp: strict scenario validation with
// errors naming the key, overrides, and JSON file loading.
#include "common/io/config.hpp"
#include "test/config_error.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "common/node/site_context.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using Catch::Contains;
using nlohmann::json;
using rnav::ConfigError;
using rnav::Scenario;
using rnav_test::config_error;

namespace {

std::string from_json_error(const json& j) { return config_error([&] { Scenario::from_json(j); }); }

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "rnav_test_config_XXXXXX").string();
    path = mkdtemp(tmpl.data());
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    const auto f = path / name;
    std::ofstream(f) << text;
    return f.string();
  }
};

}  // namespace

TEST_CASE("empty scenario gives the documented defaults", "[config]") {
  const Scenario sc = Scenario::from_json(json::object());
  CHECK(sc.name == "paper");
  CHECK(sc.trajectory.start_x_m == 30860);
  CHECK(sc.prl.bias_range_m == 6);
  CHECK(sc.prl_bias.switch_time_s == 400);
  // azimuth reference default: landing heading + 180, in [0, 360)
  CHECK(sc.radar.azimuth_reference_deg == Approx(295.9 - 180).epsilon(1e-12));
  CHECK(rnav::to_us(0.25) == 250000);
  CHECK(rnav::to_us(1e-6 * 0.6) == 1);
}

TEST_CASE("the paper scenario file loads and equals the defaults it restates", "[config]") {
  const Scenario sc = Scenario::load(std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json");
  const Scenario d = Scenario::from_json(json::object());
  CHECK(sc.trajectory.start_z_m == d.trajectory.start_z_m);
  CHECK(sc.trajectory.glide_deg == Approx(d.trajectory.glide_deg).epsilon(1e-15));
  CHECK(sc.snsins.corr_sigma_m == d.snsins.corr_sigma_m);
  CHECK(sc.prl.noise2s_glide_deg == d.prl.noise2s_glide_deg);
}

TEST_CASE("the nodes a landing run starts: the data link only when enabled", "[config]") {
  using V = std::vector<std::string>;
  CHECK(Scenario::from_json(json::object()).node_names() == V{"trajectory", "snsins", "prl", "prl_bias", "logger"});
  CHECK(Scenario::from_json(json::parse(R"({"datalink": {"enabled": true}})")).node_names() ==
        V{"trajectory", "snsins", "datalink", "prl", "prl_bias", "logger"});
  CHECK(Scenario::from_json(json::parse(R"({"datalink": {"enabled": false}})")).node_names().size() == 5);
}

TEST_CASE("unknown keys throw ConfigError naming the full key path", "[config]") {
  CHECK_THAT(from_json_error(json::parse(R"({"prl": {"bias_rang_m": 1}})")),
             Contains("prl.bias_rang_m"));
  CHECK_THAT(from_json_error(json::parse(R"({"trajectroy": {}})")), Contains("trajectroy"));
  CHECK_THAT(from_json_error(json::parse(R"({"snsins": {"corr_sigma_m": 2, "latncy_s": 0.1}})")),
             Contains("snsins.latncy_s"));
}

TEST_CASE("an unknown key names the nearest known key of its section, if one is near", "[config]") {
  CHECK_THAT(from_json_error(json::parse(R"({"radar": {"x_n": -900}})")),
             Contains("radar.x_n (did you mean 'radar.x_m'?)"));
  CHECK_THAT(from_json_error(json::parse(R"({"trajectroy": {}})")),
             Contains("trajectroy (did you mean 'trajectory'?)"));
  CHECK_THAT(from_json_error(json::parse(R"({"prl": {"bias_rang_m": 1}})")),
             Contains("(did you mean 'prl.bias_range_m'?)"));
  // Far from every key of its section: no guess (x_m is a radar key, not a prl one).
  const std::string far = from_json_error(json::parse(R"({"prl": {"x_m": 1}})"));
  CHECK_THAT(far, Contains("prl.x_m"));
  CHECK_THAT(far, !Contains("did you mean"));
  // Each of several unknown keys gets its own guess.
  const std::string two = from_json_error(json::parse(R"({"radar": {"x_n": 1, "z_n": 2}})"));
  CHECK_THAT(two, Contains("radar.x_n (did you mean 'radar.x_m'?)"));
  CHECK_THAT(two, Contains("radar.z_n (did you mean 'radar.z_m'?)"));
}

TEST_CASE("unknown keys in several sections and at the top are named in one error", "[config]") {
  // Three sections read in turn and a top-level key: each named, with its own guess.
  const std::string m = from_json_error(
      json::parse(R"({"radar": {"x_n": 1}, "prl": {"bias_rang_m": 1}, "runner": {"window": 1}, "nmae": "x"})"));
  CHECK_THAT(m, Contains("radar.x_n (did you mean 'radar.x_m'?)"));
  CHECK_THAT(m, Contains("prl.bias_rang_m (did you mean 'prl.bias_range_m'?)"));
  CHECK_THAT(m, Contains("runner.window"));
  CHECK_THAT(m, Contains("nmae (did you mean 'name'?)"));
  // The azimuth-only scenario's nested "origin" and its sections too.
  const std::string u = config_error([] {
    rnav::UavScenario::from_json(json::parse(R"({"origin": {"lat": 1}, "uav": {"radius": 1}})"));
  });
  CHECK_THAT(u, Contains("origin.lat"));
  CHECK_THAT(u, Contains("uav.radius"));
  // A reader of some sections only (the nodes' shared site context) still names theirs, both.
  const std::string s = config_error(
      [] { rnav::read_site_context(json::parse(R"({"radar": {"x_n": 1}, "runner": {"windw_s": 1}, "prl": {"q": 1}})")); });
  CHECK_THAT(s, Contains("radar.x_n"));
  CHECK_THAT(s, Contains("runner.windw_s"));
  CHECK_THAT(s, !Contains("prl.q"));  // not its section
}

TEST_CASE("bad values throw ConfigError naming the key", "[config]") {
  SECTION("string \"NaN\"") {
    const std::string m = from_json_error(json::parse(R"({"prl": {"bias_range_m": "NaN"}})"));
    CHECK_THAT(m, Contains("prl.bias_range_m"));
    CHECK_THAT(m, Contains("number"));
  }
  SECTION("a real NaN / infinity in the document") {
    json j;
    j["prl"]["bias_course_deg"] = std::nan("");
    CHECK_THAT(from_json_error(j), Contains("prl.bias_course_deg"));
    json k;
    k["snsins"]["latency_s"] = std::numeric_limits<double>::infinity();
    CHECK_THAT(from_json_error(k), Contains("snsins.latency_s"));
  }
  SECTION("out of range") {
    const std::string m = from_json_error(json::parse(R"({"prl": {"noise2s_range_m": -1}})"));
    CHECK_THAT(m, Contains("prl.noise2s_range_m"));
    CHECK_THAT(m, Contains("out of range"));
    CHECK_THAT(from_json_error(json::parse(R"({"trajectory": {"speed_mps": 301}})")),
               Contains("trajectory.speed_mps"));
    // the bounds themselves are accepted
    CHECK_NOTHROW(Scenario::from_json(json::parse(R"({"trajectory": {"speed_mps": 300}})")));
  }
  SECTION("wrong type") {
    CHECK_THAT(from_json_error(json::parse(R"({"trajectory": {"speed_mps": "fast"}})")),
               Contains("trajectory.speed_mps"));
    CHECK_THAT(from_json_error(json::parse(R"({"prl_bias": {"add_nav_variance": 1}})")),
               Contains("prl_bias.add_nav_variance"));
    CHECK_THAT(from_json_error(json::parse(R"({"runner": {"max_attempts": 2.5}})")),
               Contains("runner.max_attempts"));
    CHECK_THAT(from_json_error(json::parse(R"({"name": 5})")), Contains("name"));
    CHECK_THAT(from_json_error(json::parse(R"({"prl": 5})")), Contains("prl"));
    CHECK_THAT(from_json_error(json::parse(R"({"logger": {"table_ranges_m": [25000, "x"]}})")),
               Contains("logger.table_ranges_m"));
  }
  SECTION("period not a multiple of the truth step") {
    const std::string m = from_json_error(json::parse(R"({"prl": {"period_s": 0.3}})"));
    CHECK_THAT(m, Contains("prl.period_s"));
    CHECK_THAT(m, Contains("trajectory.step_s"));
    CHECK_THAT(from_json_error(json::parse(R"({"snsins": {"link_phase_s": 0.1}})")),
               Contains("snsins.link_phase_s"));
    CHECK_NOTHROW(Scenario::from_json(json::parse(R"({"prl": {"period_s": 0.5}})")));
    CHECK_NOTHROW(
        Scenario::from_json(json::parse(R"({"prl": {"period_s": 0.3}, "trajectory": {"step_s": 0.05}})")));
    // runner.window_s: 0 (the default: the whole realization), else a multiple of the step.
    CHECK(Scenario::from_json(json::parse("{}")).runner.window_s == 0);
    CHECK_THAT(from_json_error(json::parse(R"({"runner": {"window_s": 0.1}})")), Contains("runner.window_s"));
    CHECK_THAT(from_json_error(json::parse(R"({"runner": {"window_s": -1}})")), Contains("runner.window_s"));
    CHECK_NOTHROW(Scenario::from_json(json::parse(R"({"runner": {"window_s": 37}})")));
  }
  SECTION("bad intervals") {
    CHECK_THAT(from_json_error(json::parse(R"({"snsins": {"dropouts": [[10, 5]]}})")),
               Contains("snsins.dropouts"));
    CHECK_THAT(from_json_error(json::parse(R"({"snsins": {"dropouts": [[1, 2, 3]]}})")),
               Contains("snsins.dropouts"));
    const Scenario sc = Scenario::from_json(json::parse(R"({"snsins": {"dropouts": [[100, 120.5]]}})"));
    REQUIRE(sc.snsins.dropouts.size() == 1);
    CHECK(sc.snsins.dropouts[0].first == 100);
    CHECK(sc.snsins.dropouts[0].second == 120.5);
  }
  SECTION("inconsistent combinations") {
    CHECK_THAT(from_json_error(json::parse(R"({"runner": {"flush_s": 1}})")),
               Contains("runner.flush_s"));
    CHECK_THAT(from_json_error(json::parse(R"({"trajectory": {"end_x_m": 30000}})")),
               Contains("trajectory.end_x_m"));
    CHECK_THAT(from_json_error(json::parse(R"({"logger": {"table_ranges_m": []}})")),
               Contains("logger.table_ranges_m"));
  }
}

TEST_CASE("apply_override sets nested keys with JSON or string values", "[config]") {
  json doc = json::parse(R"({"prl": {"bias_range_m": 6}})");
  rnav::apply_override(doc, "prl.bias_range_m=7.5");
  rnav::apply_override(doc, "prl_bias.switch_time_s=300");
  rnav::apply_override(doc, "name=my run");
  rnav::apply_override(doc, "logger.table_ranges_m=[20000,5000]");
  rnav::apply_override(doc, "prl_bias.add_nav_variance=false");
  rnav::apply_override(doc, "a.b.c=1");
  CHECK(doc["prl"]["bias_range_m"].is_number());
  CHECK(doc["prl"]["bias_range_m"].get<double>() == 7.5);
  CHECK(doc["prl_bias"]["switch_time_s"].get<double>() == 300);
  CHECK(doc["name"].get<std::string>() == "my run");
  CHECK(doc["a"]["b"]["c"].get<int>() == 1);
  doc.erase("a");
  const Scenario sc = Scenario::from_json(doc);
  CHECK(sc.prl.bias_range_m == 7.5);
  CHECK(sc.prl_bias.switch_time_s == 300);
  CHECK(sc.name == "my run");
  CHECK(sc.logger.table_ranges_m == std::vector<double>{20000, 5000});
  CHECK_FALSE(sc.prl_bias.add_nav_variance);

  json bad = json::parse(R"({"prl": 5})");
  CHECK_THROWS_AS(rnav::apply_override(bad, "prl.bias_range_m=1"), ConfigError);
  CHECK_THROWS_AS(rnav::apply_override(bad, "no_equals_sign"), ConfigError);
  CHECK_THROWS_AS(rnav::apply_override(bad, "=5"), ConfigError);
  CHECK_THROWS_AS(rnav::apply_override(bad, "a..b=5"), ConfigError);
}

TEST_CASE("load_json_file and Scenario::load name the file", "[config]") {
  TempDir dir;
  const std::string broken = dir.write("broken.json", "{\"prl\": {\"bias_range_m\": 6,,}\n");
  const std::string m = config_error([&] { rnav::load_json_file(broken); });
  CHECK_THAT(m, Contains(broken));
  CHECK_THAT(config_error([&] { rnav::load_json_file((dir.path / "missing.json").string()); }),
             Contains("missing.json"));
  // comments are allowed (the shipped scenarios use them)
  const std::string ok = dir.write("ok.json", "// comment\n{\"prl\": {\"bias_range_m\": 3} /* c */}\n");
  CHECK(rnav::load_json_file(ok)["prl"]["bias_range_m"].get<double>() == 3);
  // Scenario::load applies overrides, and its errors name both file and key
  const Scenario sc = Scenario::load(ok, {"prl.bias_course_deg=0.2"});
  CHECK(sc.prl.bias_range_m == 3);
  CHECK(sc.prl.bias_course_deg == 0.2);
  const std::string m2 = config_error([&] { Scenario::load(ok, {"prl.bias_rang_m=1"}); });
  CHECK_THAT(m2, Contains(ok));
  CHECK_THAT(m2, Contains("prl.bias_rang_m"));
}

TEST_CASE("command-line integers: whole text, in range, never truncated", "[config][input]") {
  CHECK(rnav::parse_integer("--realizations", "7", 1, 1000000000) == 7);
  CHECK(rnav::parse_integer("--seed", "-12", -100, 100) == -12);
  // 4294967297 = 2^32 + 1 used to run one realization (truncated to int).
  CHECK_THROWS_WITH(rnav::parse_integer("--realizations", "4294967297", 1, 1000000000),
                    Catch::Contains("--realizations: 4294967297 is outside [1, 1000000000]"));
  CHECK_THROWS_WITH(rnav::parse_integer("--realizations", "12x", 1, 10), Catch::Contains("'12x' is not an integer"));
  CHECK_THROWS_WITH(rnav::parse_integer("--realizations", "", 1, 10), Catch::Contains("'' is not an integer"));
  CHECK_THROWS_WITH(rnav::parse_integer("--realizations", " 5", 1, 10), Catch::Contains("is not an integer"));
  CHECK_THROWS_WITH(rnav::parse_integer("--realizations", "-3", 1, 10), Catch::Contains("outside [1, 10]"));
  // all digits beyond long long: an integer out of range, said so (it used to be "not an integer")
  CHECK_THROWS_WITH(rnav::parse_integer("--seed", "18446744073709551615", -5, 5),
                    Catch::Contains("--seed: 18446744073709551615 is outside [-5, 5]"));
  CHECK_THROWS_WITH(rnav::parse_integer("--seed", "1844674407370955161x", -5, 5), Catch::Contains("not an integer"));
}

TEST_CASE("overrides and JSON numbers: null is no value, an overflow is named with its key", "[config][input]") {
  nlohmann::json doc = nlohmann::json::object();
  // null used to read as "the key left out": the default, silently
  CHECK_THROWS_WITH(rnav::apply_override(doc, "prl.period_s=null"),
                    Catch::Contains("override 'prl.period_s=null': null is not a value"));
  CHECK_THROWS_WITH(rnav::apply_override(doc, "prl.period_s=1e400"),
                    Catch::Contains("override 'prl.period_s=1e400': the number overflows the double range"));
  CHECK_THROWS_WITH(rnav::parse_json_checked(std::string(R"({"prl": {"period_s": 1e400}})"), "big.json", true),
                    Catch::Contains("big.json: a number overflows the double range (at or after key 'period_s')"));
}

TEST_CASE("JSON input: a repeated key and deep nesting are errors, not the last value or a crash", "[config][input]") {
  CHECK_THROWS_WITH(rnav::parse_json_checked(std::string(R"({"radar": {"x_m": 1, "x_m": 2}})"), "scenario.json", true),
                    Catch::Contains("scenario.json: key 'x_m' appears twice in one object"));
  // The same key in two objects is fine.
  CHECK(rnav::parse_json_checked(std::string(R"({"a": {"x": 1}, "b": {"x": 2}})"), "s", true)["b"]["x"] == 2);
  // 70 000 levels (it overflowed the stack): stopped at the limit while parsing.
  const std::string deep = std::string(70000, '[') + std::string(70000, ']');
  CHECK_THROWS_WITH(rnav::parse_json_checked(deep, "deep.json", false),
                    Catch::Contains("deep.json: JSON nested deeper than 64 levels"));
  const std::string ok = std::string(60, '[') + std::string(60, ']');
  CHECK_NOTHROW(rnav::parse_json_checked(ok, "ok.json", false));
}
