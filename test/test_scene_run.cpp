// A recorded scene as a run (kind "scene"): its truth, one process per sensor and its logger,
// exchanging LCM messages like the other scenarios' processes (scripts/run), or the same nodes in
// one process (rnav_inproc). Checked on a recording of the suite's own generator
// (scene_recording_gen.hpp, times in Unix seconds as real recordings stamp them):
//   - each realization the logger writes is what build/bin/rnav_scene simulate writes for the
//     same seed and realization, byte for byte, and summary.json counts what it holds;
//   - the multi-process run over LCM (batches of 10 s, and one message per sample in windows of
//     0.5 s) writes the in-process run's files, byte for byte;
//   - the loop over LCM: a radar bias hidden in the recording, diagnosed, the report given as
//     the run's errors (--effects), and the diagnosis of the run's recording names it again,
//     its estimate within its standard errors of the injected value; the nominal run's does not;
//   - bad input named: no recording, a sensor the recording lacks, --effects on a UAV scenario;
//   - a landing flight's scenario (rnav_scene scenario): run over LCM as in one process, with
//     its report's range bias.
#include "estimators/diagnosis/multi_diagnose.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"
#include "test/scene_recording_gen.hpp"
#include "test/shell.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace fs = std::filesystem;
using namespace rnav_test;
using namespace rnav_test::scene_gen;

namespace {

const std::string kRoot = RNAV_SOURCE_DIR, kBin = std::string(RNAV_BINARY_DIR) + "/bin";
constexpr double kUnixT0 = 1.7e9 + 0.25;  // [s] the recording's first time stamp: Unix seconds
constexpr std::uint64_t kRecordingSeed = 5;
// The scene options the generator needs: its noise and its radar's gate (scene_validation's test).
const nlohmann::json kScene = {{"sigma_bearing_deg", 0.3}, {"sigma_range_m", 2}, {"gate_position_m", 30}, {"calibration_seed", 7}};
const std::string kSimOptions = " --sigma-deg 0.3 --sigma-range-m 2 --gate-m 30 ";

// The generator's recording in d/rec and a scene scenario d/scene.json replaying it (plus `extra` keys of "scene").
void make_scene(const fs::path& d, double bias_rad, const nlohmann::json& extra = nlohmann::json::object(), long recordings = 3) {
  recording(kRecordingSeed, bias_rad, kUnixT0).write_folder((d / "rec").string());
  nlohmann::json sc = {{"name", "gen"}, {"kind", "scene"}, {"scene", kScene}, {"logger", {{"recordings", recordings}}}};
  sc["scene"]["recording"] = "rec";
  for (const auto& [k, v] : extra.items()) sc["scene"][k] = v;
  std::ofstream((d / "scene.json").string()) << sc.dump(1);
}

// The files of two folders, equal byte for byte (each name of a's in b too; hidden files aside).
void same_folder(const fs::path& a, const fs::path& b) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(a)) {
    if (!e.is_regular_file() || e.path().filename().string()[0] == '.') continue;  // rnav_scene's output marker
    INFO(e.path() << " against " << b / e.path().filename());
    REQUIRE(fs::exists(b / e.path().filename()));
    CHECK(slurp(e.path()) == slurp(b / e.path().filename()));
    ++n;
  }
  CHECK(n >= 4);  // observer.csv, detections.csv, truth.csv and their units
}

std::string folder(int k) {
  char b[32];
  std::snprintf(b, sizeof b, "realization_%06d", k);
  return b;
}

// The named effects of a report: (name, sensor) -> (estimate, stderr) of its first parameter.
std::map<std::pair<std::string, std::string>, std::pair<double, double>> named(const nlohmann::json& rep) {
  std::map<std::pair<std::string, std::string>, std::pair<double, double>> m;
  for (const auto& e : rep["effects"]) {
    const auto& sc = e["scope"];
    const std::string sensor = sc.contains("sensor") && sc["sensor"].is_string() ? sc["sensor"].get<std::string>() : "";
    const auto& est = e["estimate"];
    const auto& se = e["stderr"];
    m[{e["name"].get<std::string>(), sensor}] = {est.is_array() ? est.back().get<double>() : est.get<double>(),
                                                  se.is_array() ? se.back().get<double>() : se.get<double>()};
  }
  return m;
}

}  // namespace

TEST_CASE("scene run: each realization as rnav_scene simulate writes it, and the summary counts them", "[scene]") {
  const fs::path d = scratch("scene_run_inproc");
  make_scene(d, kRadarBiasRad);
  sh_ok(kBin + "/rnav_inproc --scenario " + (d / "scene.json").string() + " --realizations 3 --seed 7 --out " + (d / "out").string());
  double radar_rows = 0;
  for (int k = 0; k < 3; ++k) {
    const fs::path e = d / ("expect" + std::to_string(k));
    sh_ok(kBin + "/rnav_scene simulate " + (d / "rec").string() + kSimOptions + "--seed 7 --realization " + std::to_string(k) +
          " --out " + e.string());
    same_folder(e, d / "out" / folder(k));
    const auto sim = rnav::MultiSensorData::read_folder(e.string());
    for (const auto& x : sim.detections) radar_rows += x.sensor == "radar" && !x.empty_scan();
  }
  CHECK_FALSE(fs::exists(d / "out" / folder(3)));
  const auto j = nlohmann::json::parse(slurp(d / "out" / "summary.json"));
  CHECK(j["realizations"] == 3);
  CHECK(j["kind"] == "scene");
  CHECK(j["sensors"]["radar"]["detections"]["mean"].get<double>() == Approx(radar_rows / 3).epsilon(1e-12));
  CHECK(j["sensors"]["eo"]["clutter"]["mean"].get<double>() == 0);  // the generator's camera sees no clutter
  CHECK(j["sensors"]["radar"]["clutter"]["mean"].get<double>() > 50);       // one replayed return per 2 s scan, ~117 scans
  // a realization differs from the next (its own streams)
  CHECK(slurp(d / "out" / folder(0) / "detections.csv") != slurp(d / "out" / folder(1) / "detections.csv"));
  // the recording's own observer and truth, through the truth node and the logger
  const auto real = rnav::MultiSensorData::read_folder((d / "rec").string());
  const auto sim = rnav::MultiSensorData::read_folder((d / "out" / folder(0)).string());
  REQUIRE(sim.observer.size() == real.observer.size());
  CHECK(sim.observer.front().t_s == real.observer.front().t_s);
  CHECK(sim.truth.at("2").back().t_s == real.truth.at("2").back().t_s);
}

TEST_CASE("scene run: separate processes over LCM write the in-process run's files, byte for byte", "[scene][integration]") {
  const fs::path d = scratch("scene_run_lcm");
  make_scene(d, kRadarBiasRad);
  const std::string scen = (d / "scene.json").string();
  sh_ok(kBin + "/rnav_inproc --scenario " + scen + " --realizations 3 --seed 7 --out " + (d / "inproc").string());
  for (const std::string wire : {"batch", "sample"}) {
    const fs::path out = d / ("lcm_" + wire);
    const std::string set = wire == "sample" ? " --set runner.wire=sample --set runner.window_s=0.5" : "";
    const std::string log = sh_ok(kRoot + "/scripts/run " + scen + " --realizations 3 --seed 7 --net netns --out " + out.string() + set);
    INFO(log);
    CHECK(slurp(out / "summary.json") == slurp(d / "inproc" / "summary.json"));
    for (int k = 0; k < 3; ++k) same_folder(d / "inproc" / folder(k), out / folder(k));
    // one process per sensor, each naming what it published
    for (const std::string s : {"radar", "eo"}) {
      const std::string node_log = slurp(out / "logs" / ("scene_sensor@" + s + ".log"));
      std::string upper = s;
      for (auto& c : upper) c = static_cast<char>(std::toupper(c));
      CHECK(node_log.find("published SCENE_DETECTIONS_" + upper + "=") != std::string::npos);
    }
    CHECK(slurp(out / "logs" / "scene_truth.log").find("SCENE_OBSERVER=") != std::string::npos);
  }
}

TEST_CASE("scene run: a hidden radar bias diagnosed, injected over LCM and named again, and not without it", "[scene][integration]") {
  const fs::path d = scratch("scene_run_loop");
  make_scene(d, kRadarBiasRad, nlohmann::json::object(), 1);
  rnav::MultiDiagnoseOptions mo;
  mo.association.gate_position_m = 30;
  mo.sigma_bearing_deg = 0.3;
  mo.sigma_range_m = 2;
  const auto real = rnav::diagnose_multi(rnav::MultiSensorData::read_folder((d / "rec").string()), mo);
  std::ofstream((d / "report.json").string()) << real.to_json().dump(1);
  const auto injected = named(nlohmann::json::parse(real.to_json().dump()));
  const auto key = std::make_pair(std::string("bearing_bias"), std::string("radar"));
  INFO(real.text());
  REQUIRE(injected.count(key));
  const std::string scen = (d / "scene.json").string();
  for (const bool extended : {true, false}) {
    const fs::path out = d / (extended ? "extended" : "nominal");
    sh_ok(kRoot + "/scripts/run " + scen + " --realizations 1 --seed 3 --net netns --out " + out.string() +
          (extended ? " --effects " + (d / "report.json").string() : ""));
    const auto rep = rnav::diagnose_multi(rnav::MultiSensorData::read_folder((out / folder(0)).string()), mo);
    const auto found = named(nlohmann::json::parse(rep.to_json().dump()));
    INFO((extended ? "extended" : "nominal") << ": " << rep.text());
    if (!extended) {
      CHECK_FALSE(found.count(key));
      continue;
    }
    REQUIRE(found.count(key));
    // The re-estimate scatters about the injected value with the simulation's own standard
    // error (one realization): 4 of its stated standard errors is the bound (two-sided 1e-4).
    const auto [est, se] = found.at(key);
    CHECK(std::abs(est - injected.at(key).first) < 4 * se);
  }
}

TEST_CASE("scene run: a scenario without a recording, a sensor it lacks and --effects on a UAV scenario are named", "[scene]") {
  const fs::path d = scratch("scene_run_errors");
  make_scene(d, 0);
  std::ofstream((d / "norec.json").string()) << R"({"kind": "scene", "scene": {"sigma_bearing_deg": 0.3}})";
  auto r = sh(kBin + "/rnav_clock --scenario " + (d / "norec.json").string() + " --check");
  CHECK(r.status == 2);
  CHECK(r.output.find("scene.recording") != std::string::npos);
  r = sh(kBin + "/rnav_scene_sensor --scenario " + (d / "scene.json").string() + " --instance radr");
  CHECK(r.status == 2);
  CHECK(r.output.find("radar") != std::string::npos);  // did you mean, and the list
  CHECK(r.output.find("eo") != std::string::npos);
  r = sh(kRoot + "/scripts/run uav --effects " + (d / "scene.json").string() + " --realizations 1 --out " + (d / "uav").string());
  CHECK(r.status != 0);
  CHECK(r.output.find("--effects applies to") != std::string::npos);
  // the nodes a run of it starts: its truth, one per sensor, its logger
  CHECK(sh_ok(kBin + "/rnav_clock --scenario " + (d / "scene.json").string() + " --print-nodes") ==
        "scene_truth,scene_sensor@eo,scene_sensor@radar,scene_logger\n");
}

TEST_CASE("scene validation of a landing flight: a range bias of the independent generator found outside the nominal band, inside the extended", "[scene]") {
  const fs::path d = scratch("scene_prl_validate");
  // the independent generator's flight (its own geodesy, kinematics and noise) with a 60 m range bias
  sh_ok("/usr/bin/python3 " + kRoot + "/scripts/flightgen.py landing " + (d / "flight").string() +
        " --seed 3 --set range_bias_m=60 --set geometry=straight > /dev/null");
  sh_ok(kRoot + "/scripts/diagnose prl " + (d / "flight").string() + " --injections 0 --json " + (d / "report.json").string());
  // the base scenario: the generator's white noise (2 sigma), no constant bias of the paper's radar
  std::ofstream((d / "base.json").string())
      << R"({"prl": {"bias_range_m": 0, "bias_course_deg": 0, "bias_glide_deg": 0, "noise2s_range_m": 24, "noise2s_course_deg": 0.5,
                     "noise2s_glide_deg": 0.6, "max_range_m": 200000}})";
  sh_ok(kBin + "/rnav_scene validate " + (d / "flight").string() + " --scenario " + (d / "base.json").string() + " --effects " +
        (d / "report.json").string() + " --runs 40 --json " + (d / "v.json").string());
  const auto v = nlohmann::json::parse(slurp(d / "v.json"));
  // z of the real value in a band taken as the 5-95 % quantiles of a normal: sigma = width / 3.29.
  auto z = [&](const std::string& model, const std::string& q, const std::string& st) {
    for (const auto& r : v["rows"])
      if (r["model"] == model && r["quantity"] == q && r["statistic"] == st) {
        const double lo = r["band_lo"], hi = r["band_hi"], x = r["real"];
        return (x - 0.5 * (lo + hi)) / ((hi - lo) / 3.29);
      }
    FAIL("no row " << model << " " << q << " " << st);
    return 0.0;
  };
  // 60 m against a band about 1.2 m wide per sigma: tens of sigmas without the bias; with the
  // report's bias within 4 (two-sided 6e-5 for a normal; the band's quantiles from 40 runs
  // carry about 20 % error in width).
  CHECK(z("nominal", "range", "mean") > 10);
  CHECK(std::abs(z("extended", "range", "mean")) < 4);
  CHECK(std::abs(z("extended", "range", "sd")) < 4);
  CHECK(std::abs(z("extended", "elevation", "mean")) < 4);
}

// A landing flight as a scenario that scripts/run runs as separate processes: rnav_scene scenario
// writes the flight's landing scenario (extended by its report), and the run over LCM writes the
// in-process run's realizations byte for byte. The report's constant range bias is the scenario's
// radar bias (no drift named: b_sim = b), and replay.csv holds every nav sample of the flight.
TEST_CASE("scene scenario of a landing flight: run over LCM as in one process, with the report's range bias", "[scene][integration]") {
  const fs::path d = scratch("scene_prl_scenario");
  sh_ok("/usr/bin/python3 " + kRoot + "/scripts/flightgen.py landing " + (d / "flight").string() +
        " --seed 3 --set range_bias_m=60 --set geometry=straight > /dev/null");
  sh_ok(kRoot + "/scripts/diagnose prl " + (d / "flight").string() + " --injections 0 --json " + (d / "report.json").string());
  std::ofstream((d / "base.json").string()) << R"({"prl": {"bias_range_m": 0, "max_range_m": 200000}})";
  sh_ok(kBin + "/rnav_scene scenario " + (d / "flight").string() + " --scenario " + (d / "base.json").string() + " --effects " +
        (d / "report.json").string() + " --out " + (d / "sc").string());
  const auto sc = nlohmann::json::parse(slurp(d / "sc" / "scenario.json"));
  const auto rep = nlohmann::json::parse(slurp(d / "report.json"));
  double range_bias = NAN;
  for (const auto& e : rep["effects"])
    if (e.value("nominal", false) && e["name"] == "range_bias") range_bias = e["estimate"];
  CHECK(sc["kind"] == "prl");
  CHECK(sc["trajectory"]["replay_csv"] == "replay.csv");
  CHECK(sc["prl"]["bias_range_m"].get<double>() == Approx(range_bias).margin(1e-9));
  CHECK(std::abs(range_bias - 60) < 10);  // the generator's 60 m, found (its SE is about 1 m)
  auto lines = [](const std::string& s) { return std::count(s.begin(), s.end(), '\n'); };
  CHECK(lines(slurp(d / "sc" / "replay.csv")) == lines(slurp(d / "flight" / "nav.csv")));
  const std::string scen = (d / "sc" / "scenario.json").string();
  sh_ok(kBin + "/rnav_inproc --scenario " + scen + " --realizations 3 --seed 7 --out " + (d / "inproc").string());
  INFO(sh_ok(kRoot + "/scripts/run " + scen + " --realizations 3 --seed 7 --net netns --out " + (d / "lcm").string()));
  CHECK(slurp(d / "lcm" / "realizations.csv") == slurp(d / "inproc" / "realizations.csv"));
  CHECK(lines(slurp(d / "lcm" / "realizations.csv")) > 3);
}

TEST_CASE("scene scenario: --out is required, and a landing flight's closure is refused naming what replays it", "[scene]") {
  const fs::path d = scratch("scene_scenario_errors");
  sh_ok("/usr/bin/python3 " + kRoot + "/scripts/flightgen.py landing " + (d / "flight").string() + " --seed 3 > /dev/null");
  auto r = sh(kBin + "/rnav_scene scenario " + (d / "flight").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("--out DIR is required") != std::string::npos);
  r = sh(kBin + "/rnav_scene closure " + (d / "flight").string() + " --effects x.json");
  CHECK(r.status == 2);
  CHECK(r.output.find("validate and scenario replay it") != std::string::npos);
}

TEST_CASE("scene scenario: scene.noise chooses the report's simulated or identified noise, as rnav_scene --noise", "[scene]") {
  // A report whose radar:1:bearing channel was identified at 0.01 rad and is drawn at 0.03 rad
  // (its slow wander): a scenario draws the latter by default and the former with
  // scene.noise=identified (the key rnav_scene scenario --noise writes; it was not written, and
  // an LCM run drew the simulated noise whatever --noise said).
  const fs::path d = scratch("scene_scenario_noise");
  make_scene(d, 0);
  const nlohmann::json report = {
      {"kind", "multi"},
      {"effects", nlohmann::json::array()},
      {"noise",
       {{"radar:1:bearing",
         {{"sigma", 0.01}, {"correlated_share", 0}, {"outlier_fraction", 0}, {"nominal_share", 0},
          {"simulated", {{"model", "gauss_markov"}, {"sigma", 0.03}, {"tau_s", 50}, {"correlated_share", 0.99}, {"slow_wander", true}}}}}}}};
  std::ofstream((d / "report.json").string()) << report.dump(1);
  const std::string scen = (d / "scene.json").string(), rep = "scene.effects_report=" + (d / "report.json").string();
  auto sigma = [&](const std::vector<std::string>& overrides) {
    const auto sc = rnav::SceneScenario::load(scen, overrides);
    return std::sqrt(sc.setup->errors.noise.at("radar:1:bearing").s2);
  };
  CHECK(sigma({rep}) == Approx(0.03));
  CHECK(sigma({rep, "scene.noise=identified"}) == Approx(0.01));
  CHECK_THROWS_WITH(rnav::SceneScenario::load(scen, {rep, "scene.noise=drawn"}), Catch::Contains("noise"));
}
