// The main loop of a free-running node (FreeNode): parse the command line, load the scenario,
// print the options, then handle LCM messages until SIGINT/SIGTERM or, with --idle-exit-s, until
// the input has been silent that long; then take what is still queued and flush (decide and
// publish what is still waiting) and exit 0.
#pragma once

#include "config.hpp"
#include "free_node.hpp"
#include "lcm_bus.hpp"
#include "node_main.hpp"

#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace rnav {

struct FreeArgs {
  std::string scenario_file;
  std::vector<std::string> overrides;  // --set key=value
  std::string lcm_url;                 // --lcm-url
  double idle_exit_s = 0;              // [s wall] --idle-exit-s: 0 = run until a signal
  std::string record_file;             // --record FILE: every published message, as an LCM log
  std::vector<std::string> extra;      // the node's own options, as (name, value) pairs
};

/// [ms wall] On a stop signal the node keeps taking messages until none came for this long.
inline constexpr int kDrainQuietMs = 200;

/// Install SIGINT/SIGTERM handlers that only set a flag; true once either arrived.
void install_stop_signals();
bool stop_requested();

/// Usage: NAME --free --scenario FILE [--set k=v]... [--lcm-url URL] [--idle-exit-s S]
///        [--record FILE] [node options]
/// `make` builds the node on the bus from the scenario and the node's own options (it throws
/// ConfigError on one it does not know). Returns the process exit code; never calls exit().
template <class Sc>
int run_free_main(int argc, char** argv, const std::string& name,
                  const std::function<std::unique_ptr<FreeNode>(Bus&, const Sc&, const FreeArgs&)>& make) {
  try {
    FreeArgs args;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw ConfigError("option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--free") continue;
      if (a == "--scenario") args.scenario_file = value();
      else if (a == "--set") args.overrides.push_back(value());
      else if (a == "--lcm-url") args.lcm_url = value();
      else if (a == "--record") args.record_file = value();
      else if (a == "--idle-exit-s") args.idle_exit_s = parse_number("--idle-exit-s", value(), 0, 1e6);
      else if (a.rfind("--", 0) == 0) { args.extra.push_back(a); args.extra.push_back(value()); }
      else throw ConfigError("unexpected argument '" + a + "'");
    }
    if (args.scenario_file.empty()) throw ConfigError("--scenario FILE is required");
    const Sc sc = Sc::load(args.scenario_file, args.overrides);
    std::cerr << name << ": free-running (no lock-step clock); options\n";
    sc.print(std::cerr);
    LcmBus bus(args.lcm_url);
    if (!args.record_file.empty()) bus.record_publishes(args.record_file);
    auto node = make(bus, sc, args);
    install_stop_signals();
    long seen = -1;
    double last_input_s = wall_seconds();
    std::cerr << name << ": listening\n";
    while (!stop_requested()) {
      bus.handle(50);
      const double now = wall_seconds();
      if (node->received() != seen) { seen = node->received(); last_input_s = now; }
      if (args.idle_exit_s > 0 && now - last_input_s >= args.idle_exit_s) break;
    }
    // Take what is still queued (until the input pauses for kDrainQuietMs), then decide the rest.
    while (bus.handle(kDrainQuietMs)) {}
    node->flush();
    bus.finish_record();
    std::cerr << name << ": finished: " << node->summary() << "\n";
    return 0;
  } catch (const ConfigError& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace rnav
