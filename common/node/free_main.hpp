// The main loop of a free-running node (FreeNode): parse the command line, load the scenario,
// print the options, then handle LCM messages until SIGINT/SIGTERM or, with --idle-exit-s, until
// the input has been silent that long; then take what is still queued and flush (decide and
// publish what is still waiting) and exit 0.
#pragma once

#include "common/io/cli.hpp"
#include "common/io/config.hpp"
#include "common/node/free_node.hpp"
#include "common/node/lcm_bus.hpp"
#include "common/node/node_main.hpp"

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
};

/// [ms wall] On a stop signal the node keeps taking messages until none came for this long.
inline constexpr int kDrainQuietMs = 200;

/// Install SIGINT/SIGTERM handlers that only set a flag; true once either arrived.
void install_stop_signals();
bool stop_requested();

/// The option table of a free-running node (--free, --scenario, --set, --lcm-url, --idle-exit-s,
/// --record), filling `args`; the node adds its own options to it.
cli::Parser free_parser(const NodeProgram& p, FreeArgs& args);

/// Usage: PROGRAM --free --scenario FILE [--set k=v]... [--lcm-url URL] [--idle-exit-s S]
///        [--record FILE] [node options]
/// `add_options` adds the node's own options to the parser; `make` builds the node on the bus.
/// Returns the process exit code; never calls exit().
template <class Sc>
int run_free_main(int argc, char** argv, const NodeProgram& p, const std::function<void(cli::Parser&)>& add_options,
                  const std::function<std::unique_ptr<FreeNode>(Bus&, const Sc&)>& make) {
  return cli::guarded_main(p.program, [&]() -> int {
    FreeArgs args;
    cli::Parser parser = free_parser(p, args);
    add_options(parser);
    if (!parser.parse(argc, argv, std::cout)) return 0;
    if (args.scenario_file.empty()) throw ConfigError("--scenario FILE is required (see " + p.program + " --free --help)");
    const Sc sc = Sc::load(args.scenario_file, args.overrides);
    std::cerr << p.name << ": free-running (no lock-step clock); options\n";
    sc.print(std::cerr);
    LcmBus bus(args.lcm_url);
    if (!args.record_file.empty()) bus.record_publishes(args.record_file);
    auto node = make(bus, sc);
    install_stop_signals();
    long seen = -1;
    double last_input_s = wall_seconds();
    std::cerr << p.name << ": listening\n";
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
    std::cerr << p.name << ": finished: " << node->summary() << "\n";
    return 0;
  });
}

}  // namespace rnav
