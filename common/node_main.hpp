// The shared main loop of a node process: parse the common command line, load the scenario,
// print the options, run the node over LCM until FINISH/ABORT. Process mains stay thin.
#pragma once

#include "lockstep_node.hpp"
#include "scenario.hpp"

#include <functional>
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

/// Usage: NAME --scenario FILE [--set k=v]... [--drop CH:R:W[:A]]... [--lcm-url URL] [--out DIR]
/// `make` builds the node on the bus. Returns the process exit code; never calls exit().
int run_node_main(int argc, char** argv, const std::string& name,
                  const std::function<std::unique_ptr<LockstepNode>(Bus&, const Scenario&,
                                                                    const NodeArgs&)>& make);

/// Monotonic wall time [s].
double wall_seconds();

}  // namespace rnav
