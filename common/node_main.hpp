// The shared main loop of a node process: parse the common command line, load the scenario,
// print the options, run the node over LCM until FINISH/ABORT. Process mains stay thin.
#pragma once

#include "lcm_bus.hpp"
#include "lockstep_node.hpp"
#include "scenario.hpp"

#include <functional>
#include <iostream>
#include <memory>
#include <string>

namespace rnav {

struct NodeArgs {
  std::string scenario_file;
  std::vector<std::string> overrides;   // --set key=value
  std::vector<DropSpec> drops;          // --drop CHANNEL:R:W[:A]
  std::string lcm_url;                  // --lcm-url
  std::string out_dir;                  // --out (logger)
  std::vector<std::string> extra;       // anything else, for the node
};

/// Monotonic wall time [s].
double wall_seconds();

/// Usage: NAME --scenario FILE [--set k=v]... [--drop CH:R:W[:A]]... [--lcm-url URL] [--out DIR]
/// Sc is the scenario type (Scenario, UavScenario): Sc::load(file, overrides), Sc::print(os).
/// `make` builds the node on the bus. Returns the process exit code; never calls exit().
template <class Sc>
int run_node_main(int argc, char** argv, const std::string& name,
                  const std::function<std::unique_ptr<LockstepNode>(Bus&, const Sc&,
                                                                    const NodeArgs&)>& make) {
  try {
    NodeArgs args;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw ConfigError(name + ": option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--scenario") args.scenario_file = value();
      else if (a == "--set") args.overrides.push_back(value());
      else if (a == "--drop") args.drops.push_back(DropSpec::parse(value()));
      else if (a == "--lcm-url") args.lcm_url = value();
      else if (a == "--out") args.out_dir = value();
      else args.extra.push_back(a);
    }
    if (args.scenario_file.empty()) throw ConfigError(name + ": --scenario FILE is required");
    const Sc sc = Sc::load(args.scenario_file, args.overrides);
    std::cerr << name << ": options\n";
    sc.print(std::cerr);
    LcmBus bus(args.lcm_url);
    auto node = make(bus, sc, args);
    for (const auto& d : args.drops) node->add_drop(d);
    while (!node->done()) {
      bus.handle(20);
      node->poll(wall_seconds());
    }
    if (node->exit_code() == 0)
      std::cerr << name << ": finished (" << node->duplicates_ignored() << " resent batch(es) ignored, "
                << node->republished() << " republished)\n";
    else
      std::cerr << name << ": " << (node->exit_code() == 3 ? "" : "error: ") << node->failure() << "\n";
    return node->exit_code();
  } catch (const ConfigError& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 1;
  }
}


}  // namespace rnav
