#include "common/node/free_main.hpp"

#include <csignal>

namespace rnav {

namespace {
volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_stop_signal(int) { g_stop = 1; }
}  // namespace

void install_stop_signals() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() { return g_stop != 0; }

cli::Parser free_parser(const NodeProgram& p, FreeArgs& args) {
  cli::Parser parser(p.program,
                     "--free --scenario FILE [--set key=value]... [--lcm-url URL] [--idle-exit-s S] [--record FILE]",
                     p.does +
                         "\n\nFree-running: no lock-step clock. Inputs are taken as they come, either as the "
                         "lock-step batches of a replayed log (processed per window, outputs as batches) or one "
                         "sample per message (outputs one per sample), and decided from their own time stamps. "
                         "SIGINT/SIGTERM: take what is queued, decide what waits, publish, exit 0. scripts/replay "
                         "plays a log into it.");
  parser.flag("--free", "run without the lock-step clock (this mode)", [] {})
      .value("--scenario", "FILE", "scenario JSON file (sim/scenarios/*.json)", "required", args.scenario_file)
      .repeated("--set", "key=value", "override a scenario key, e.g. --set prl_bias.nav_wait_s=2", args.overrides)
      .value("--lcm-url", "URL", "LCM provider URL", "$LCM_DEFAULT_URL, else LCM's default", args.lcm_url)
      .value("--idle-exit-s", "S", "[s wall] exit (after deciding what waits) when no input came for S seconds; 0: never",
             "0", [&args](const std::string& v) { args.idle_exit_s = cli::number("--idle-exit-s", v, 0, 1e6); })
      .value("--record", "FILE", "also write every message published into FILE as an LCM event log", "none",
             args.record_file);
  return parser;
}

}  // namespace rnav
