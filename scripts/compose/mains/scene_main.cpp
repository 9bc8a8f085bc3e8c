// rnav_scene simulate|validate|closure|scenario RECORDING [options]: a recorded scene (a multi-sensor CSV folder)
// replayed as a simulation, its sensors' errors from a diagnosis report (--effects) or nominal.
//   simulate  one realization written as a recording folder (scripts/diagnose multi reads it);
//   validate  N simulations per model (nominal, and extended with --effects) and the recording
//             placed among them per sensor:target pair (scene_validation.hpp);
//   closure   N extended simulations diagnosed: each injected effect's naming rate and the
//             mean of its estimates against the injected value (scene_closure.hpp);
//   scenario  a scenario file that scripts/run runs as separate processes over LCM: a scene
//             scenario of a multi-sensor recording, the landing scenario of a landing flight.
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "common/io/process_memory.hpp"
#include "common/io/config.hpp"
#include "common/io/did_you_mean.hpp"
#include "scripts/compose/scene/scene_closure.hpp"
#include "scripts/compose/scene/scene_effects_json.hpp"
#include "scripts/compose/scene/scene_from_recording.hpp"
#include "sim/scene/scene_sim.hpp"
#include "scripts/compose/scene/scene_validation.hpp"
#include "scripts/compose/scenario/prl_report.hpp"
#include "scripts/compose/scene/prl_validation.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <set>
#include <sstream>

namespace {

struct Args {
  std::vector<std::string> pos;
  std::string effects, out, json, name, scenario;
  std::uint64_t seed = 1, realization = 0;
  int runs = 100, threads = 2, min_n = 20;
  double sigma_deg = 0.5, sigma_range_m = 1.0;
  bool force = false;
  std::string clutter = "replay";
  std::string noise = "simulated";  ///< each channel's noise from the report: "simulated" or "identified"
  rnav::AssociationOptions assoc;
};

// The scene of recording d as the options ask (its clutter replayed or drawn).
rnav::scene::RecordedScene scene_of(const Args& a, const rnav::MultiSensorData& d, const std::string& name) {
  auto sc = rnav::scene_from_recording(d, name, a.assoc);
  for (auto& s : sc.sensors) s.replay_clutter = a.clutter == "replay";
  return sc;
}

nlohmann::json read_report(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw rnav::ConfigError("--effects " + path + ": cannot be read");
  try {
    return nlohmann::json::parse(f);
  } catch (const nlohmann::json::exception& e) {
    throw rnav::ConfigError("--effects " + path + ": not JSON (" + e.what() + ")");
  }
}

std::string fmt(double x, const char* f = "%.4g") {
  if (!std::isfinite(x)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// An angle quantity (shown in degrees, held in radians).
bool angle(const rnav::ValidationRow& r) { return r.quantity == "bearing" || r.quantity == "azimuth" || r.quantity == "elevation"; }

// A row's values in the unit shown: angles in degrees.
double shown(const rnav::ValidationRow& r, double x) {
  return angle(r) && (r.statistic == "mean" || r.statistic == "sd") ? x * 180 / M_PI : x;
}

std::string unit_of(const rnav::ValidationRow& r) {
  if (r.statistic == "lag1" || r.statistic == "detection_rate") return "1";
  return angle(r) ? "deg" : "m";
}

// Per pair: inside on every statistic (of both quantities)?
std::map<std::string, bool> pairs_inside(const std::vector<rnav::ValidationRow>& rows, int min_n, std::map<std::string, std::string>* outside) {
  std::map<std::string, bool> in;
  for (const auto& r : rows) {
    if (r.n < min_n) continue;
    auto [it, fresh] = in.emplace(r.pair, true);
    if (!r.inside) {
      it->second = false;
      if (outside) (*outside)[r.pair] += std::string((*outside)[r.pair].empty() ? "" : ", ") + r.quantity + " " + r.statistic;
    }
  }
  return in;
}

// The table, the summary per model and --json of one recording's rows per model (in order).
int report_validation(const Args& a, const std::string& name, const std::vector<std::pair<std::string, std::vector<rnav::ValidationRow>>>& by_model) {
  std::cout << "validate " << name << ": " << a.runs << " simulations per model (seed " << a.seed << "), the 5-95 % band of each statistic\n";
  std::cout << "  pair                      quantity  statistic        n       real";
  for (const auto& [label, _] : by_model) std::cout << "  " << label << " band          ";
  std::cout << "\n";
  const auto& first = by_model.front().second;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto& r = first[i];
    char line[160];
    std::snprintf(line, sizeof line, "  %-25s %-9s %-14s %5d %10s %-4s", r.pair.c_str(), r.quantity.c_str(), r.statistic.c_str(), r.n,
                  fmt(shown(r, r.real)).c_str(), unit_of(r).c_str());
    std::cout << line;
    for (const auto& [label, rows] : by_model) {
      const auto& x = rows[i];
      std::snprintf(line, sizeof line, "  [%9s, %9s] %-3s", fmt(shown(x, x.band_lo)).c_str(), fmt(shown(x, x.band_hi)).c_str(), x.inside ? "in" : "OUT");
      std::cout << line;
    }
    std::cout << "\n";
  }
  std::vector<rnav::ValidationRow> all;
  for (const auto& [label, rows] : by_model) {
    all.insert(all.end(), rows.begin(), rows.end());
    std::map<std::string, std::string> outside;
    const auto in = pairs_inside(rows, a.min_n, &outside);
    int k = 0;
    for (const auto& [p, ok] : in) k += ok;
    std::cout << "  " << label << ": " << k << " of " << in.size() << " pairs with >= " << a.min_n
              << " detections inside the band on every statistic";
    if (!outside.empty()) {
      std::cout << "; outside:";
      for (const auto& [p, what] : outside) std::cout << " " << p << " (" << what << ")";
    }
    std::cout << "\n";
  }
  if (!a.json.empty()) {
    nlohmann::ordered_json j;
    j["kind"] = "scene_validation";
    j["recording"] = name;
    j["runs"] = a.runs;
    j["seed"] = a.seed;
    j["min_n"] = a.min_n;
    j["units"] = "bearing, azimuth and elevation mean and sd in rad, range in m, lag1 and detection_rate in 1";
    j["rows"] = rnav::rows_json(all);
    rnav::write_file_atomic(a.json, j.dump(1) + "\n");
  }
  return 0;
}

int validate(const Args& a, const rnav::MultiSensorData& d, const std::string& name) {
  const rnav::scene::RecordedScene base = scene_of(a, d, name);
  const rnav::SceneStats real = rnav::scene_stats(d, a.assoc);
  const double sb = a.sigma_deg * M_PI / 180;
  std::vector<std::pair<std::string, rnav::scene::SceneErrors>> models;
  if (!a.effects.empty()) {
    const auto ext = rnav::errors_from_report(read_report(a.effects), a.effects, name, sb, a.sigma_range_m, a.noise == "simulated");
    models.push_back({"nominal", rnav::nominal_errors(ext.nominal_bearing_sigma_rad, ext.nominal_range_sigma_m)});
    models.push_back({"extended", ext});
  } else {
    models.push_back({"nominal", rnav::nominal_errors(sb, a.sigma_range_m)});
  }
  std::vector<std::pair<std::string, std::vector<rnav::ValidationRow>>> by_model;
  for (const auto& [label, err] : models) {
    rnav::scene::RecordedScene sc = base;
    rnav::calibrate_detection(sc, d, err, a.assoc, a.seed);
    const auto sims = rnav::simulated_stats(d, sc, err, a.assoc, a.runs, a.seed, a.threads);
    by_model.push_back({label, rnav::validation_rows(name, label, real, sims)});
  }
  return report_validation(a, name, by_model);
}

// The nominal landing scenario of flight f on the base scenario (--scenario, else the paper's
// defaults), its nav track written into work_dir; no radar effects.
rnav::Scenario nominal_flight_scenario(const Args& a, const rnav::PrlFlightData& f, const std::string& work_dir) {
  const rnav::Scenario base = a.scenario.empty() ? rnav::Scenario::from_json(nlohmann::json::object()) : rnav::Scenario::load(a.scenario);
  rnav::Scenario sc = rnav::scenario_of_flight(f, base, work_dir);
  sc.prl_effects = rnav::PrlEffectsOptions{};
  return sc;
}

// A landing flight (site.json, radar.csv, nav.csv): replayed on the base scenario (--scenario,
// else the paper's defaults), nominal and, with --effects (a landing-radar report), extended.
int validate_prl(const Args& a, const std::string& dir, const std::string& name) {
  const rnav::PrlFlightData f = rnav::PrlFlightData::read_folder(dir);
  const rnav::SceneStats real = rnav::prl_flight_stats(f);
  char tmpl[] = "/tmp/rnav_prl_validate_XXXXXX";
  if (!mkdtemp(tmpl)) throw std::runtime_error("cannot create a work folder in /tmp");
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup{tmpl};
  const rnav::Scenario nominal = nominal_flight_scenario(a, f, tmpl);
  std::vector<std::pair<std::string, rnav::Scenario>> models{{"nominal", nominal}};
  if (!a.effects.empty()) {
    models.push_back({"extended", rnav::extended_scenario(f, nominal, read_report(a.effects), a.effects)});
  }
  std::vector<std::pair<std::string, std::vector<rnav::ValidationRow>>> by_model;
  for (const auto& [label, sc] : models)
    by_model.push_back({label, rnav::validation_rows(name, label, real, rnav::simulated_flight_stats(sc, a.runs, static_cast<std::int64_t>(a.seed), tmpl))});
  return report_validation(a, name, by_model);
}

// The landing scenario of a flight (nominal, or extended with --effects) written to --out DIR.
int scenario_prl(const Args& a, const std::string& dir) {
  const rnav::PrlFlightData f = rnav::PrlFlightData::read_folder(dir);
  rnav::prepare_output_dir(a.out, a.force);
  rnav::Scenario sc = nominal_flight_scenario(a, f, a.out);
  if (!a.effects.empty()) sc = rnav::extended_scenario(f, sc, read_report(a.effects), a.effects);
  const std::string file = rnav::write_flight_scenario(sc, a.out);
  std::cout << "scenario " << file << ": the landing flight " << dir << " (" << (a.effects.empty() ? "nominal" : "extended by " + a.effects)
            << "); run it with scripts/run " << file << "\n";
  return 0;
}

// The scene scenario of a multi-sensor recording written to --out DIR/scenario.json: the recording
// (and the report, with --effects) named relative to the file, the options given here.
int scenario_scene(const Args& a, const std::string& dir, const std::string& name) {
  rnav::MultiSensorData::read_folder(dir);  // a recording the scene can replay, checked now rather than at run time
  rnav::prepare_output_dir(a.out, a.force);
  const std::filesystem::path out = std::filesystem::absolute(a.out);
  auto rel = [&out](const std::string& p) { return std::filesystem::absolute(p).lexically_normal().lexically_relative(out).string(); };
  nlohmann::ordered_json scene = {{"recording", rel(dir)}, {"name", name}, {"clutter", a.clutter}, {"noise", a.noise},
                                  {"sigma_bearing_deg", a.sigma_deg}, {"sigma_range_m", a.sigma_range_m},
                                  {"gate_bearing_deg", a.assoc.gate_bearing_deg}, {"gate_position_m", a.assoc.gate_position_m},
                                  {"reference_max_gap_s", a.assoc.reference_max_gap_s}, {"calibration_seed", a.seed}};
  if (!a.effects.empty()) scene["effects_report"] = rel(a.effects);
  const nlohmann::ordered_json doc = {{"name", name}, {"kind", "scene"}, {"scene", scene}};
  const std::string file = (out / "scenario.json").string();
  rnav::write_file_atomic(file, doc.dump(2) + "\n");
  std::cout << "scenario " << file << ": the recorded scene " << dir << " (" << (a.effects.empty() ? "nominal" : "extended by " + a.effects)
            << "); run it with scripts/run " << file << "\n";
  return 0;
}

int closure(const Args& a, const rnav::MultiSensorData& d, const std::string& name) {
  if (a.effects.empty()) throw rnav::ConfigError("closure: --effects REPORT.json is required (the effects to inject and re-find)");
  const auto err = rnav::errors_from_report(read_report(a.effects), a.effects, name, a.sigma_deg * M_PI / 180, a.sigma_range_m, a.noise == "simulated");
  auto sc = scene_of(a, d, name);
  rnav::calibrate_detection(sc, d, err, a.assoc, a.seed);
  rnav::MultiDiagnoseOptions mo;
  mo.association = a.assoc;
  mo.sigma_bearing_deg = err.nominal_bearing_sigma_rad * 180 / M_PI;
  mo.sigma_range_m = err.nominal_range_sigma_m;
  mo.search.threads = a.threads;
  const auto rows = rnav::scene_closure(d, sc, err, mo, a.runs, a.seed);
  std::cout << "closure " << name << ": " << a.runs << " simulations extended by " << a.effects << ", each diagnosed\n";
  int all_named = 0, all_within = 0;
  for (const auto& r : rows) {
    std::cout << "  " << r.injected.name << " [" << (r.injected.sensor.empty() ? "-" : r.injected.sensor) << ":"
              << (r.injected.target.empty() ? "-" : r.injected.target) << "]: named " << r.named << " of " << r.runs;
    bool within = r.named > 0;
    for (std::size_t p = 0; p < r.injected.theta.size(); ++p) {
      std::cout << (p ? "; " : "; injected ") << fmt(r.injected.theta[p], "%.4g") << ", mean " << fmt(r.mean[p], "%.4g") << " (sd "
                << fmt(r.sd[p], "%.3g") << ")" << (r.within_2se[p] ? " within 2 SE" : " NOT within 2 SE");
      within = within && r.within_2se[p];
    }
    std::cout << "\n";
    all_named += 10 * r.named >= 9 * r.runs;
    all_within += within;
  }
  std::cout << "  named in >= 90 %: " << all_named << " of " << rows.size() << " effects; mean within 2 SE: " << all_within << " of "
            << rows.size() << "\n";
  if (!a.json.empty()) {
    nlohmann::ordered_json j;
    j["kind"] = "scene_closure";
    j["recording"] = name;
    j["runs"] = a.runs;
    j["seed"] = a.seed;
    j["effects"] = rnav::closure_json(rows);
    rnav::write_file_atomic(a.json, j.dump(1) + "\n");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  rnav::cli::keep_freed_memory();
  return rnav::cli::guarded_main("rnav_scene", [&]() -> int {
    Args a;
    rnav::cli::Parser p("rnav_scene", "simulate RECORDING --out DIR [--effects REPORT.json] [--seed S] [--realization K]\n"
                                      "validate RECORDING [--effects REPORT.json] [--runs N] [--json FILE]\n"
                                      "closure RECORDING --effects REPORT.json [--runs N] [--json FILE]\n"
                                      "scenario RECORDING|FLIGHT --out DIR [--effects REPORT.json] [--scenario BASE.json]",
                        "A recorded scene (a multi-sensor CSV folder: observer.csv, detections.csv, truth.csv) replayed as a "
                        "simulation: the observer's and the targets' reference tracks are the truth; each sensor scans at its "
                        "recorded times, covers the bearings and ranges the recording shows, detects each target with the "
                        "probability measured there and adds the recording's clutter. Its errors: a diagnosis report's named "
                        "effects and each channel's identified noise (--effects, rnav_diagnose multi --json), or the nominal "
                        "model (white noise at the nominal sigmas). simulate writes one realization as a recording folder; "
                        "validate runs --runs simulations per model and places the recording among them per sensor:target "
                        "pair (residual mean, sd, lag-1 autocorrelation, detection rate; the 5-95 % band); closure diagnoses "
                        "--runs extended simulations and says how often each injected effect is named and how close the "
                        "mean estimate comes to the injected value; scenario writes DIR/scenario.json, which scripts/run runs as "
                        "separate processes over LCM (a scene scenario of the recording, or the landing scenario of a landing "
                        "flight, a folder with site.json: its nav track in DIR/replay.csv).");
    auto num = [](const char* opt, double& x, double lo, double hi) {
      return [opt, &x, lo, hi](const std::string& v) { x = rnav::cli::number(opt, v, lo, hi); };
    };
    auto integer = [](const char* opt, auto& x, long long lo, long long hi) {
      return [opt, &x, lo, hi](const std::string& v) { x = static_cast<std::remove_reference_t<decltype(x)>>(rnav::parse_integer(opt, v, lo, hi)); };
    };
    constexpr long long kMaxSeed = std::numeric_limits<long long>::max();
    p.value("--effects", "REPORT.json", "the extended model: a multi-sensor diagnosis report of this recording (pooled or alone)", "none (nominal)", a.effects)
        .value("--out", "DIR", "simulate: the recording folder written; scenario: the folder of scenario.json; new, empty or an earlier output unless --force",
               "required for simulate and scenario", a.out)
        .flag("--force", "simulate, scenario: write into --out DIR whatever it holds", a.force)
        .value("--seed", "S", "seed of the simulations' random streams, >= 0", "1", integer("--seed", a.seed, 0, kMaxSeed))
        .value("--realization", "K", "simulate: which realization of the seed, >= 0", "0", integer("--realization", a.realization, 0, kMaxSeed))
        .value("--runs", "N", "validate: simulations per model; closure: simulations diagnosed, >= 20", "100", integer("--runs", a.runs, 20, 100000))
        .value("--threads", "N", "validate: simulations at once; closure: the diagnosis's threads, >= 1 (the result does not depend on it)", "2", integer("--threads", a.threads, 1, 256))
        .value("--min-n", "N", "validate: a pair counts in the summary with at least N associated detections", "20", integer("--min-n", a.min_n, 1, 1000000))
        .value("--json", "FILE", "validate, closure: write the rows as JSON", "none", a.json)
        .value("--clutter", "replay|draw",
               "the recording's clutter replayed in its own scans (land, piers and buoys where they are), or drawn: a Poisson "
               "count per scan at the recording's mean, each return drawn from its returns",
               "replay", [&a](const std::string& v) {
                 if (v != "replay" && v != "draw")
                   throw rnav::ConfigError("--clutter must be replay or draw, not '" + v + "'" + rnav::did_you_mean(v, {"replay", "draw"}));
                 a.clutter = v;
               })
        .value("--noise", "simulated|identified",
               "with --effects, each channel's noise: the report's simulated noise (its identified noise with the slow wander no "
               "named effect explains), or the identified noise findings alone (fitted with a trend, correlation times up to a "
               "quarter of the series)",
               "simulated", [&a](const std::string& v) {
                 if (v != "simulated" && v != "identified")
                   throw rnav::ConfigError("--noise must be simulated or identified, not '" + v + "'" +
                                           rnav::did_you_mean(v, {"simulated", "identified"}));
                 a.noise = v;
               })
        .value("--scenario", "FILE",
               "validate and scenario of a landing flight (a folder with site.json): the landing scenario whose radar and navigation "
               "models the flight is replayed on (its site, trajectory and radar timing are the flight's)",
               "the paper's defaults (sim/scenarios/paper.json)", a.scenario)
        .value("--name", "NAME", "the recording's name (a pooled report's recording scope)", "the folder's name", a.name)
        .value("--sigma-deg", "D", "nominal bearing noise, 1 sigma [deg] (with --effects: the report's)", "0.5 deg", num("--sigma-deg", a.sigma_deg, 1e-6, 90))
        .value("--sigma-range-m", "M", "nominal range noise, 1 sigma [m] (with --effects: the report's)", "1 m", num("--sigma-range-m", a.sigma_range_m, 1e-6, 1e5))
        .value("--gate-deg", "D", "association gate of bearings [deg], as rnav_diagnose multi", "3 deg", num("--gate-deg", a.assoc.gate_bearing_deg, 1e-3, 45))
        .value("--gate-m", "M", "association gate of range sensors [m], as rnav_diagnose multi", "20 m", num("--gate-m", a.assoc.gate_position_m, 1e-3, 1e5))
        .value("--reference-max-gap", "S", "a reference is interpolated only across gaps this short [s], as rnav_diagnose multi", "2 s",
               num("--reference-max-gap", a.assoc.reference_max_gap_s, 1e-3, 1e5))
        .positionals("simulate|validate|closure|scenario RECORDING", "the command and the recording folder", [&a](const std::string& v) { a.pos.push_back(v); });
    if (!p.parse(argc, argv, std::cout)) return 0;
    std::vector<std::string> missing;
    if (a.pos.empty()) missing.push_back("the command (simulate, validate, closure or scenario)");
    if (a.pos.size() < 2) missing.push_back("RECORDING (a multi-sensor CSV folder)");
    if (!missing.empty()) {
      std::string m;
      for (const auto& x : missing) m += (m.empty() ? "" : " and ") + x;
      throw rnav::ConfigError(m + (missing.size() > 1 ? " are" : " is") + " required (see rnav_scene --help)");
    }
    if (a.pos.size() > 2) throw rnav::ConfigError("one RECORDING only, not '" + a.pos[2] + "'");
    const std::string& cmd = a.pos[0];
    if (cmd != "simulate" && cmd != "validate" && cmd != "closure" && cmd != "scenario")
      throw rnav::ConfigError("unknown command '" + cmd + "'" + rnav::did_you_mean(cmd, {"simulate", "validate", "closure", "scenario"}) +
                              " (simulate, validate, closure or scenario)");
    if (cmd == "scenario" && a.out.empty()) throw rnav::ConfigError("scenario: --out DIR is required");
    const std::string name = a.name.empty() ? rnav::recording_folder_name(a.pos[1]) : a.name;
    // a landing flight (site.json beside radar.csv): validate and scenario
    if (std::filesystem::exists(std::filesystem::path(a.pos[1]) / "site.json")) {
      if (cmd == "scenario") return scenario_prl(a, a.pos[1]);
      if (cmd != "validate")
        throw rnav::ConfigError(a.pos[1] + " is a landing flight (site.json): validate and scenario replay it (simulate: scripts/run "
                                "the scenario that 'rnav_scene scenario' writes; closure with scripts/discovery_study)");
      return validate_prl(a, a.pos[1], name);
    }
    if (!a.scenario.empty()) throw rnav::ConfigError("--scenario applies to a landing flight (a folder with site.json) only");
    const auto d = rnav::MultiSensorData::read_folder(a.pos[1]);
    if (cmd == "validate") return validate(a, d, name);
    if (cmd == "closure") return closure(a, d, name);
    if (cmd == "scenario") return scenario_scene(a, a.pos[1], name);
    if (a.out.empty()) throw rnav::ConfigError("simulate: --out DIR is required");
    const double sb = a.sigma_deg * M_PI / 180;
    const auto err = a.effects.empty() ? rnav::nominal_errors(sb, a.sigma_range_m)
                                       : rnav::errors_from_report(read_report(a.effects), a.effects, name, sb, a.sigma_range_m, a.noise == "simulated");
    auto sc = scene_of(a, d, name);
    rnav::calibrate_detection(sc, d, err, a.assoc, a.seed);
    const auto det = rnav::scene::simulate(sc, err, a.seed, a.realization);
    rnav::prepare_output_dir(a.out, a.force);
    rnav::recording_of(d, det).write_folder(a.out);
    std::cerr << "rnav_scene: " << det.size() << " detection rows of " << sc.sensors.size() << " sensors ("
              << (a.effects.empty() ? "nominal" : "extended by " + a.effects) << ", seed " << a.seed << ", realization " << a.realization
              << ") into " << a.out << "\n";
    return 0;
  });
}
