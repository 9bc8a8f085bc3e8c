// rnav_merge: join shards of one ensemble (runs over disjoint realization ranges) into the
// outputs of one run of the whole ensemble, byte for byte (shard_merge.hpp).
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "scripts/compose/merge/shard_merge.hpp"

#include <iostream>

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_merge", [&]() -> int {
    std::string out;
    bool force = false;
    std::vector<std::string> shards;
    rnav::cli::Parser p("rnav_merge", "--out DIR [--force] SHARD_DIR...",
                        "Joins shards of one ensemble - output folders of runs of the same scenario and seed over "
                        "disjoint realization ranges (scripts/run or rnav_inproc with --first-realization, or the "
                        "ranks of rnav_mpi) - into the statistics one run of all realizations writes, byte for byte "
                        "(sums are held exactly in each shard's ensemble_state.json). The shards may be given in any "
                        "order; together they must hold realizations 0 ... N-1, each once.");
    p.value("--out", "DIR", "results folder; it must be new, empty or an earlier output (its .rnav-output marker) unless --force",
            "required", out)
        .flag("--force", "write into --out DIR whatever it holds", force)
        .positionals("SHARD_DIR", "a shard's output folder (scenario.json, ensemble_state.json, ...)",
                     [&](const std::string& v) { shards.push_back(v); });
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (out.empty()) throw rnav::ConfigError("--out DIR is required (see rnav_merge --help)");
    if (shards.empty()) throw rnav::ConfigError("no SHARD_DIR given (see rnav_merge --help)");
    rnav::prepare_output_dir(out, force);
    const auto r = rnav::merge_shards(shards, out);
    std::cerr << "merge: " << shards.size() << " shards, " << r.realizations << " realizations (" << r.kind
              << ", seed " << r.seed << ") into " << out << "\n";
    return 0;
  });
}
