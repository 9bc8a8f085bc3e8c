// Process "clock": drives the lock-step protocol over LCM (Conductor) and shows progress.
// Usage: rnav_clock --scenario FILE [--set k=v]... --realizations N --seed S
//                   --nodes a,b,c [--realtime [--speed X]] [--events FILE] [--lcm-url URL]
//        rnav_clock --scenario FILE [--set k=v]... --check   (validate, print, exit)
//        rnav_clock --print-kind FILE                        (prl or uav)
#include "approach_trajectory.hpp"
#include "atomic_file.hpp"
#include "conductor.hpp"
#include "lcm_bus.hpp"
#include "node_main.hpp"
#include "progress.hpp"
#include "uav_scenario.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iostream>
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
    j["resends"].push_back({{"realization", e.realization}, {"attempt", e.attempt}, {"window", e.window}, {"reason", e.reason}});
  rnav::write_file_atomic(file, j.dump(2) + "\n");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string scenario_file, events, url, nodes;
    std::vector<std::string> overrides;
    rnav::ConductorOptions o;
    bool check = false;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw rnav::ConfigError("clock: option " + a + " needs a value");
        return argv[++i];
      };
      auto integer = [&](const std::string& v) -> long {
        std::size_t pos = 0;
        long x = 0;
        try {
          x = std::stol(v, &pos);
        } catch (const std::exception&) {
          pos = 0;
        }
        if (pos != v.size() || v.empty()) throw rnav::ConfigError("clock: " + a + " '" + v + "' is not an integer");
        return x;
      };
      if (a == "--scenario") scenario_file = value();
      else if (a == "--set") overrides.push_back(value());
      else if (a == "--realizations") o.n_realizations = static_cast<int>(rnav::parse_integer(a, value(), 1, 1000000000));
      else if (a == "--seed") o.seed = integer(value());
      else if (a == "--nodes") nodes = value();
      else if (a == "--realtime") o.realtime = true;
      else if (a == "--speed") o.speed = std::stod(value());
      else if (a == "--events") events = value();
      else if (a == "--lcm-url") url = value();
      else if (a == "--check") check = true;
      else if (a == "--print-kind") {
        std::cout << rnav::scenario_kind(value()) << "\n";
        return 0;
      }
      else throw rnav::ConfigError("clock: unknown option " + a);
    }
    if (scenario_file.empty()) throw rnav::ConfigError("clock: --scenario FILE is required");
    // What the clock needs of a scenario: lock-step options, truth step, duration.
    rnav::RunnerOptions runner;
    double step_s = 0, duration_s = 0;
    if (rnav::scenario_kind(scenario_file) == "uav") {
      const auto sc = rnav::UavScenario::load(scenario_file, overrides);
      runner = sc.runner;
      step_s = sc.sensor.period_s;
      duration_s = sc.duration_s;
      if (check) {
        sc.print(std::cout);
        std::cout << "step_s=" << step_s << " duration_s=" << duration_s << " orbit_period_s=" << sc.orbit_period_s()
                  << " eval_time_s=" << sc.eval_time_s() << "\n";
        return 0;
      }
    } else {
      const auto sc = rnav::Scenario::load(scenario_file, overrides);
      const auto traj = rnav::make_trajectory(sc);
      runner = sc.runner;
      step_s = sc.trajectory.step_s;
      duration_s = traj->duration_s();
      if (check) {
        sc.print(std::cout);
        std::cout << "step_s=" << step_s << " duration_s=" << duration_s;
        if (const auto* a = dynamic_cast<const rnav::ApproachTrajectory*>(traj.get()))
          std::cout << " turn_radius_m=" << a->turn_radius_m() << " final_from_s=" << a->final_time_s()
                    << " descent_x_m=" << a->descent_x_m();
        else
          std::cout << " replay_csv=" << sc.trajectory.replay_csv;
        std::cout << "\n";
        return 0;
      }
    }
    std::stringstream ss(nodes);
    for (std::string n; std::getline(ss, n, ',');)
      if (!n.empty()) o.nodes.push_back(n);
    // Event logs of the run (lcm-logger) carry the scenario as run: the file with the overrides.
    nlohmann::json doc = rnav::load_json_file(scenario_file);
    for (const auto& ov : overrides) rnav::apply_override(doc, ov);
    o.scenario_kind = rnav::scenario_kind(scenario_file);
    o.scenario_source = scenario_file;
    o.scenario_json = doc.dump();
    rnav::LcmBus bus(url);
    rnav::Conductor c(bus, runner, step_s, o, duration_s);
    rnav::ProgressBar bar(o.realtime ? "realtime" : "ensemble");
    const double t0 = rnav::wall_seconds();
    c.on_progress = [&](int done, int total, int retries) { bar.update(done, total, retries, rnav::wall_seconds()); };
    bar.update(0, o.n_realizations, 0, t0);
    while (!c.done()) {
      bus.handle(static_cast<int>(std::ceil(1000 * c.idle_s(rnav::wall_seconds()))));
      c.poll(rnav::wall_seconds());
    }
    const double wall = rnav::wall_seconds() - t0;
    write_events(events, c, o.n_realizations, o.seed, wall);
    for (const auto& e : c.retries())
      std::cerr << "clock: realization " << e.realization << " attempt " << e.attempt
                << " repeated: " << e.reason << "\n";
    if (c.exit_code() != 0) {
      std::cerr << "clock: run failed: " << c.failure() << "\n";
      return c.exit_code();
    }
    std::cerr << "clock: " << o.n_realizations << " realizations in " << wall << " s, "
              << c.resends().size() << " RESEND(s), " << c.retries().size() << " repeated\n";
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "clock: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "clock: error: " << e.what() << "\n";
    return 1;
  }
}
