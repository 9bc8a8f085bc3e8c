// The shared main loop of a node process: parse the common command line, load the scenario,
// print the options, run the node over LCM until FINISH/ABORT. Process mains stay thin.
#pragma once

#include "common/io/cli.hpp"
#include "common/node/lcm_bus.hpp"
#include "common/node/lockstep_node.hpp"
#include "common/io/config.hpp"

#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>

namespace rnav {

struct NodeArgs {
  std::string scenario_file;
  std::vector<std::string> overrides;   // --set key=value
  std::vector<DropSpec> drops;          // --drop CHANNEL:R:W[:A[:K]]
  std::string lcm_url;                  // --lcm-url
  std::string out_dir;                  // --out (loggers only)
  std::string instance;                 // --instance (a node of which a run starts several, e.g. one per sensor)
};

/// What a node's process is, for its --help and its messages.
struct NodeProgram {
  std::string program;      ///< the binary's name, e.g. "rnav_prl": usage line and errors
  std::string name;         ///< the node's name in its log lines, e.g. "prl"
  std::string does;         ///< what it does, for --help
  bool writes_out = false;  ///< a logger: --out DIR (required) is where it writes its results
  bool has_free_mode = false;  ///< an estimator: --free runs it without the clock (free_main.hpp)
  /// A node a run starts once per instance (a scene's sensors): --instance NAME (required) says
  /// which; its node name is "NAME@INSTANCE" (scripts/run passes what follows the @).
  std::string instance_of{};   ///< what an instance is, for --help (e.g. "the sensor"); "" for a single node
};

/// Monotonic wall time [s].
double wall_seconds();

/// The option table every node shares (--scenario, --set, --drop, --lcm-url, --print-options;
/// --out for a logger), filling `args`; `print_options` is set by --print-options.
cli::Parser node_parser(const NodeProgram& p, NodeArgs& args, bool& print_options);

/// The line "NAME: published CHANNEL=N ..." of the distinct messages (a resend counted once) a
/// node published on its data channels (the control channels SIM_WINDOW, SIM_ACK and
/// SIM_SCENARIO left out: a node's first HELLOs may go out before a recorder listens). scripts/run --lcm-log sums these lines over the nodes' logs and
/// names every channel lcm-logger's recording holds fewer messages of. Nothing if none.
void print_published(std::ostream& os, const std::string& name, const std::map<std::string, long>& counts);

/// Usage: PROGRAM --scenario FILE [--set k=v]... [--drop CH:R:W[:A[:K]]]... [--lcm-url URL] [--out DIR]
/// Sc is the scenario type (Scenario, UavScenario): Sc::load(file, overrides), Sc::print(os).
/// `make` builds the node on the bus. Returns the process exit code; never calls exit().
template <class Sc>
int run_node_main(int argc, char** argv, const NodeProgram& p,
                  const std::function<std::unique_ptr<LockstepNode>(Bus&, const Sc&,
                                                                    const NodeArgs&)>& make) {
  return cli::guarded_main(p.program, [&]() -> int {
    NodeArgs args;
    bool print_options = false;
    if (!node_parser(p, args, print_options).parse(argc, argv, std::cout)) return 0;
    cli::require(p.program, {{"--scenario FILE", !args.scenario_file.empty()},
                             {"--out DIR", !p.writes_out || !args.out_dir.empty()},
                             {"--instance NAME", p.instance_of.empty() || !args.instance.empty()}});
    const Sc sc = Sc::load(args.scenario_file, args.overrides);
    if (print_options) {
      sc.print(std::cout);
      return 0;
    }
    std::cerr << p.name << ": options\n";
    sc.print(std::cerr);
    LcmBus bus(args.lcm_url);
    auto node = make(bus, sc, args);
    node->set_wire(parse_wire(sc.runner.wire));
    for (const auto& d : args.drops) node->add_drop(d);
    while (!node->done()) {
      bus.handle(20);
      node->poll(wall_seconds());
    }
    if (node->exit_code() == 0) {
      std::cerr << p.name << ": finished (" << node->duplicates_ignored() << " resent batch(es) ignored, "
                << node->republished() << " republished)\n";
      print_published(std::cerr, p.name, bus.published_counts());
    }
    else if (node->exit_code() == 3)  // aborted by the clock, which says why
      std::cerr << p.name << ": " << node->failure() << "\n";
    else
      std::cerr << cli::error_line(p.program, node->failure()) << "\n";
    return node->exit_code();
  });
}


}  // namespace rnav
