#include "common/node/node_main.hpp"

#include "common/node/channels.hpp"

#include <chrono>
#include <ostream>

namespace rnav {

void print_published(std::ostream& os, const std::string& name, const std::map<std::string, long>& counts) {
  std::string line;
  for (const auto& [channel, n] : counts)
    if (channel != ch::kWindow && channel != ch::kAck && channel != ch::kScenario)
      line += " " + channel + "=" + std::to_string(n);
  if (!line.empty()) os << name << ": published" << line << "\n";
}

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

cli::Parser node_parser(const NodeProgram& p, NodeArgs& args, bool& print_options) {
  cli::Parser parser(p.program,
                     "--scenario FILE [--set key=value]... [--drop CH:R:W[:A[:K]]]... [--lcm-url URL]" +
                         std::string(p.writes_out ? " --out DIR" : "") + std::string(p.instance_of.empty() ? "" : " --instance NAME") +
                         "\n--scenario FILE [--set key=value]... --print-options",
                     p.does +
                         "\n\nA node of the lock-step simulation: it waits for the clock (rnav_clock) on "
                         "LCM, processes each window it is granted and exits when the clock finishes "
                         "the run. scripts/run starts every node with the right arguments.");
  parser.value("--scenario", "FILE", "scenario JSON file (sim/scenarios/*.json)", "required", args.scenario_file)
      .repeated("--set", "key=value",
                "override a scenario key, e.g. --set radar.x_m=-1200 (units in the key's name: _m metres, "
                "_s seconds, _deg degrees)",
                args.overrides)
      .repeated("--drop", "CH:R:W[:A[:K]]",
                "fault injection: do not publish channel CH's batch of realization R, window W (attempt A, default "
                "every attempt; its first K transmissions, default every one)",
                [&args](const std::string& v) { args.drops.push_back(DropSpec::parse(v)); })
      .value("--lcm-url", "URL", "LCM provider URL", "$LCM_DEFAULT_URL, else LCM's default", args.lcm_url);
  if (p.writes_out)
    parser.value("--out", "DIR", "folder the results are written to (created if missing)", "required", args.out_dir);
  if (!p.instance_of.empty())
    parser.value("--instance", "NAME", "which instance of this node to run: " + p.instance_of, "required", args.instance);
  if (p.has_free_mode)
    parser.flag("--free",
                "run without the lock-step clock, driven by the messages' own time stamps (options: " + p.program +
                    " --free --help)",
                [] {});
  parser.flag("--print-options", "print the scenario as this node reads it (every key, with --set applied) and exit",
              print_options);
  parser.epilog(
      "Scenario keys: every key of the scenario file can be changed with --set; --print-options lists them "
      "all with their values, and docs/scenarios-and-results.md ('The paper scenario and our choices', each section's *_options.hpp) "
      "explains them. An unknown key is an error that names it and the nearest known key.");
  return parser;
}

}  // namespace rnav
