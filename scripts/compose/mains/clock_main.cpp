// Process "clock" (a composition root): drives the lock-step protocol over LCM (Conductor) and shows progress.
// Options: one table below (rnav_clock --help prints it).
#include "sim/trajectory/approach_trajectory.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "sim/clock/conductor.hpp"
#include "common/node/lcm_bus.hpp"
#include "common/node/node_main.hpp"
#include "sim/clock/progress.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/scenario/scene_scenario.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

namespace {

void write_events(const std::string& file, const rnav::Conductor& c, int n, std::int64_t seed,
                  double wall_s) {
  if (file.empty()) return;
  nlohmann::ordered_json j;
  j["realizations"] = n;
  j["seed"] = seed;
  j["exit_code"] = c.exit_code();
  j["failure"] = c.failure();
  j["wall_s"] = wall_s;
  j["windows_per_realization"] = c.windows_per_realization();
  j["retries"] = nlohmann::json::array();
  for (const auto& e : c.retries())
    j["retries"].push_back({{"realization", e.realization}, {"attempt", e.attempt}, {"reason", e.reason}});
  j["resends"] = nlohmann::json::array();
  for (const auto& e : c.resends())
    j["resends"].push_back({{"realization", e.realization}, {"attempt", e.attempt}, {"window", e.window}, {"reason", e.reason},
                                  {"wall_s", e.wall_s}, {"wait_s", e.wait_s}});
  // messages of other runs on the same network, ignored: the clock's own count and each node's
  int total = c.foreign_ignored();
  nlohmann::ordered_json nodes = nlohmann::ordered_json::object();
  for (const auto& [node, k] : c.nodes_foreign_ignored()) nodes[node] = k, total += k;
  j["foreign_messages_ignored"] = {{"total", total}, {"clock", c.foreign_ignored()}, {"nodes", nodes}};
  rnav::write_file_atomic(file, j.dump(2) + "\n");
}

// What the command line sets.
struct Options {
  std::string scenario_file, events, url, nodes, print_kind, speed;
  std::vector<std::string> overrides;
  rnav::ConductorOptions o;
  bool check = false, n_given = false, shard = false, print_nodes = false;
};

// The option table of rnav_clock (--help prints it in this order), setting a.
rnav::cli::Parser make_parser(Options& a) {
  rnav::ConductorOptions& o = a.o;
  rnav::cli::Parser p(
      "rnav_clock",
      "--scenario FILE [--set key=value]... --realizations N --seed S --nodes a,b,c [options]\n"
      "--scenario FILE [--set key=value]... --check\n"
      "--scenario FILE [--set key=value]... --print-nodes\n"
      "--print-kind FILE",
      "The clock of the lock-step simulation: grants windows of simulated time to the nodes over LCM, "
      "collects their acks, asks again for what was lost (RESEND) and repeats a realization only when a "
      "window cannot be completed; shows progress (a bar redrawn in place on a terminal, a line per 10 % "
      "otherwise). scripts/run starts it with the right arguments.");
  p.value("--scenario", "FILE", "scenario JSON file (sim/scenarios/*.json)", "required", a.scenario_file)
      .repeated("--set", "key=value", "override a scenario key, e.g. --set runner.window_s=10", a.overrides)
      .value("--realizations", "N", "ensemble size, 1 ... 1e9", "1",
             [&a](const std::string& v) {
               a.o.n_realizations = static_cast<int>(rnav::parse_integer("--realizations", v, 1, 1000000000));
               a.n_given = true;
             })
      .value("--first-realization", "F",
             "index of the first realization: run F ... F+N-1, a shard of a larger ensemble (scripts/run --ranks), 0 ... 2^31-1",
             "0",
             [&a](const std::string& v) {
               a.o.first_realization = static_cast<int>(rnav::parse_integer("--first-realization", v, 0, 2147483647));
               a.shard = true;
             })
      .value("--seed", "S", "ensemble seed (an integer); the same seed gives byte-identical statistics", "1",
             [&o](const std::string& v) {
               o.seed = rnav::parse_integer("--seed", v, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
             })
      .value("--nodes", "a,b,c", "names of the nodes that must say HELLO before the run starts, comma-separated",
             "required", a.nodes)
      .flag("--realtime", "pace the simulation to the wall clock (to watch it in lcm-spy)", o.realtime)
      .value("--speed", "X", "with --realtime: simulated seconds per wall-clock second, > 0", "1", a.speed)
      .value("--events", "FILE", "write run_events.json (wall time [s], RESENDs, repeated realizations) to FILE",
             "none", a.events)
      .value("--lcm-url", "URL", "LCM provider URL", "$LCM_DEFAULT_URL, else LCM's default", a.url)
      .flag("--check", "validate the scenario, print it and its derived times [s], and exit", a.check)
      .value("--print-kind", "FILE", "print the scenario kind of FILE (prl, uav or scene) and exit", "", a.print_kind)
      .flag("--print-nodes",
            "validate the scenario, print the nodes a run of it starts (comma-separated, each the process rnav_NAME) and exit",
            a.print_nodes)
      .epilog("Scenario keys: see --check (every key with its value) or the README; units are in the key names.");
  return p;
}

// Prints the nodes a run of the scenario starts, comma-separated.
void print_node_names(const Options& a) {
  const std::string kind = rnav::scenario_kind(a.scenario_file);
  const auto names = kind == "uav"     ? rnav::UavScenario::load(a.scenario_file, a.overrides).node_names()
                     : kind == "scene" ? rnav::SceneScenario::load(a.scenario_file, a.overrides).node_names()
                                       : rnav::Scenario::load(a.scenario_file, a.overrides).node_names();
  for (std::size_t i = 0; i < names.size(); ++i) std::cout << (i ? "," : "") << names[i];
  std::cout << "\n";
}

// What the clock needs of a scenario: lock-step options, truth step, duration.
struct ClockScenario {
  rnav::RunnerOptions runner;
  double step_s = 0, duration_s = 0;
};

// A uav scenario's clock needs (its logger's tracked realization checked); with --check, prints
// the scenario and its derived times [s] instead and returns false.
bool load_uav(const Options& a, ClockScenario& s) {
  const auto sc = rnav::UavScenario::load(a.scenario_file, a.overrides);
  s.runner = sc.runner;
  s.step_s = sc.sensor.period_s;
  s.duration_s = sc.duration_s;
  // A shard's logger.track_realization may lie in another shard: the merge checks it.
  if ((!a.check || a.n_given) && !a.shard) rnav::check_track_realization(sc.logger, a.o.n_realizations);
  if (a.check) {
    sc.print(std::cout);
    std::cout << "step_s=" << s.step_s << " duration_s=" << s.duration_s << " orbit_period_s=" << sc.orbit_period_s()
              << " eval_time_s=" << sc.eval_time_s() << "\n";
    return false;
  }
  return true;
}

// A scene scenario's clock needs (its recording read); with --check, prints the scenario and its
// derived times [s] instead and returns false.
bool load_scene(const Options& a, ClockScenario& s) {
  const auto sc = rnav::SceneScenario::load(a.scenario_file, a.overrides);
  s.runner = sc.runner;
  s.step_s = rnav::SceneScenario::kStepS;
  s.duration_s = sc.duration_s();
  if (a.check) {
    sc.print(std::cout);
    std::cout << "step_s=" << s.step_s << " duration_s=" << s.duration_s << " start_s=" << std::fixed << std::setprecision(3)
              << sc.setup->time.start_s << std::defaultfloat << " sensors=";
    for (std::size_t i = 0; i < sc.setup->sensors.size(); ++i) std::cout << (i ? "," : "") << sc.setup->sensors[i];
    std::cout << " targets=";
    for (std::size_t i = 0; i < sc.setup->targets.size(); ++i) std::cout << (i ? "," : "") << sc.setup->targets[i];
    std::cout << "\n";
    return false;
  }
  return true;
}

// A prl scenario's clock needs; with --check, prints the scenario and its derived times [s]
// instead and returns false.
bool load_prl(const Options& a, ClockScenario& s) {
  const auto sc = rnav::Scenario::load(a.scenario_file, a.overrides);
  const auto traj = rnav::make_trajectory(sc.trajectory, sc.site());
  s.runner = sc.runner;
  s.step_s = sc.trajectory.step_s;
  s.duration_s = traj->duration_s();
  if (a.check) {
    sc.print(std::cout);
    std::cout << "step_s=" << s.step_s << " duration_s=" << s.duration_s;
    if (const auto* t = dynamic_cast<const rnav::ApproachTrajectory*>(traj.get()))
      std::cout << " turn_radius_m=" << t->turn_radius_m() << " final_from_s=" << t->final_time_s()
                << " descent_x_m=" << t->descent_x_m();
    else
      std::cout << " replay_csv=" << sc.trajectory.replay_csv;
    std::cout << "\n";
    return false;
  }
  return true;
}

// Runs the ensemble: the conductor over LCM until done, progress shown, run_events.json and a
// summary written. Returns the exit code.
int run(Options& a, const ClockScenario& s) {
  rnav::ConductorOptions& o = a.o;
  std::stringstream ss(a.nodes);
  for (std::string n; std::getline(ss, n, ',');)
    if (!n.empty()) o.nodes.push_back(n);
  // Event logs of the run (lcm-logger) carry the scenario as run: the file with the overrides.
  nlohmann::json doc = rnav::load_json_file(a.scenario_file);
  for (const auto& ov : a.overrides) rnav::apply_override(doc, ov);
  o.scenario_kind = rnav::scenario_kind(a.scenario_file);
  o.scenario_source = a.scenario_file;
  o.scenario_json = doc.dump();
  rnav::LcmBus bus(a.url);
  rnav::Conductor c(bus, s.runner, s.step_s, o, s.duration_s);
  rnav::ProgressBar bar(o.realtime ? "realtime" : "ensemble");
  const double t0 = rnav::wall_seconds();
  c.on_progress = [&](int done, int total, int retries) { bar.update(done, total, retries, rnav::wall_seconds()); };
  // inside a realization, where whole realizations are too coarse (real time, or fewer than
  // ten): its share of windows and the sim time reached
  if (o.realtime || o.n_realizations < 10) c.on_window = [&](double done, int total, int retries, double sim_s, double end_s) {
    char detail[64];
    std::snprintf(detail, sizeof detail, "sim %.1f/%.1f s", sim_s, end_s);
    bar.update(done, total, retries, rnav::wall_seconds(), detail);
  };
  bar.update(0, o.n_realizations, 0, t0);
  while (!c.done()) {
    bus.handle(static_cast<int>(std::ceil(1000 * c.idle_s(rnav::wall_seconds()))));
    c.poll(rnav::wall_seconds());
  }
  const double wall = rnav::wall_seconds() - t0;
  write_events(a.events, c, o.n_realizations, o.seed, wall);
  for (const auto& e : c.retries())
    std::cerr << "clock: realization " << e.realization << " attempt " << e.attempt
              << " repeated: " << e.reason << "\n";
  if (c.exit_code() != 0) {
    std::cerr << rnav::cli::error_line("rnav_clock", "run failed: " + c.failure()) << "\n";
    return c.exit_code();
  }
  std::cerr << "clock: " << o.n_realizations << " realizations in " << wall << " s, "
            << c.resends().size() << " RESEND(s), " << c.retries().size() << " repeated\n";
  int foreign = c.foreign_ignored();
  for (const auto& [node, k] : c.nodes_foreign_ignored()) foreign += k;
  if (foreign > 0)
    std::cerr << "clock: " << foreign << " message(s) of another run on this network ignored (run_events.json "
                 "foreign_messages_ignored)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_clock", [&]() -> int {
    Options a;
    rnav::cli::Parser p = make_parser(a);
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (!a.print_kind.empty()) {
      std::cout << rnav::scenario_kind(a.print_kind) << "\n";
      return 0;
    }
    if (!a.speed.empty()) {
      if (!a.o.realtime) throw rnav::ConfigError("--speed applies only with --realtime");
      a.o.speed = rnav::cli::number("--speed", a.speed, 1e-6, 1e6);
    }
    rnav::cli::require("rnav_clock", {{"--scenario FILE", !a.scenario_file.empty()},
                                      {"--nodes a,b,c", a.check || a.print_nodes || !a.nodes.empty()}});
    if (a.print_nodes) {
      print_node_names(a);
      return 0;
    }
    ClockScenario s;
    const std::string kind = rnav::scenario_kind(a.scenario_file);
    const bool run_it = kind == "uav" ? load_uav(a, s) : kind == "scene" ? load_scene(a, s) : load_prl(a, s);
    if (!run_it) return 0;  // --check
    return run(a, s);
  });
}
