// rnav_inproc: the landing-approach ensemble in one process (same nodes, InprocBus).
// Options: one table below (rnav_inproc --help prints it).
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "common/node/node_main.hpp"

#include <iostream>
#include <limits>

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_inproc", [&]() -> int {
    std::string file, out;
    std::vector<std::string> overrides, drops;
    bool force = false;
    int n = 1, first = 0;
    bool shard = false;  // --first-realization given: a shard of a larger ensemble
    std::int64_t seed = 1;
    rnav::cli::Parser p("rnav_inproc", "--scenario FILE [--set key=value]... [--realizations N] [--first-realization F] [--seed S] [--out DIR] [--force]",
                        "The whole ensemble (landing radar, azimuth-only or recorded scene, as the scenario's kind says) in one process: "
                        "the same nodes as scripts/run, over an in-process bus instead of LCM. Its statistics are "
                        "byte-identical to the multi-process run's for the same seed (benchmark, determinism reference).");
    p.value("--scenario", "FILE", "scenario JSON file (sim/scenarios/*.json)", "required", file)
        .repeated("--set", "key=value", "override a scenario key, e.g. --set radar.x_m=-1200", overrides)
        .value("--realizations", "N", "ensemble size, 1 ... 1e9", "1",
               [&](const std::string& v) { n = static_cast<int>(rnav::parse_integer("--realizations", v, 1, 1000000000)); })
        .value("--first-realization", "F",
               "index of the first realization: run F ... F+N-1, a shard of a larger ensemble whose "
               "ensemble_state.json rnav_merge joins with the others', 0 ... 2^31-1",
               "0", [&](const std::string& v) { 
                 first = static_cast<int>(rnav::parse_integer("--first-realization", v, 0, 2147483647));
                 shard = true;
               })
        .value("--seed", "S", "ensemble seed (an integer)", "1",
               [&](const std::string& v) {
                 seed = rnav::parse_integer("--seed", v, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
               })
        .value("--out", "DIR",
               "results folder; it must be new, empty or an earlier output (its .rnav-output marker) unless --force",
               "none: statistics are computed but not written", out)
        .flag("--force", "write into --out DIR whatever it holds", force)
        .repeated("--drop", "CH:R:W[:A[:K]]",
                  "fault injection: channel CH's batch of realization R, window W is not published (attempt A, "
                  "default every attempt; its first K transmissions, default every one)",
                  drops)
        .epilog("Scenario keys: see rnav_clock --scenario FILE --check (every key with its value) or the README.");
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (file.empty()) throw rnav::ConfigError("--scenario FILE is required (see rnav_inproc --help)");
    if (!out.empty()) rnav::prepare_output_dir(out, force);
    const double t0 = rnav::wall_seconds();
    const auto uav = [&] {
      const auto sc = rnav::UavScenario::load(file, overrides);
      // A shard's logger.track_realization may lie in another shard: rnav_merge checks it.
      if (!shard) rnav::check_track_realization(sc.logger, n);
      return rnav::run_inproc_ensemble(sc, n, seed, out, drops, first);
    };
    const std::string kind = rnav::scenario_kind(file);
    const auto r = kind == "uav"     ? uav()
                   : kind == "scene" ? rnav::run_inproc_ensemble(rnav::SceneScenario::load(file, overrides), n, seed, out, drops, first)
                                     : rnav::run_inproc_ensemble(rnav::Scenario::load(file, overrides), n, seed, out, drops, first);
    if (r.exit_code != 0) {
      std::cerr << rnav::cli::error_line("rnav_inproc", "run failed: " + r.failure) << "\n";
      return r.exit_code;
    }
    std::cerr << "inproc: " << n << " realizations in " << rnav::wall_seconds() - t0 << " s, "
              << r.retries << " repeated\n";
    return 0;
  });
}
