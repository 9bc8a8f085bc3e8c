// Joining shards of one ensemble: runs of the same scenario and seed over disjoint realization
// ranges (scripts/run --first-realization, rnav_inproc --first-realization, the ranks of
// rnav_mpi) into the outputs one run of the whole ensemble writes, byte for byte.
//
// Each shard is an output folder holding scenario.json and ensemble_state.json (the exact
// sums, see ExactSum; landing: PrlStats, azimuth-only: UavStats); an azimuth-only shard also
// holds realizations.csv and, if it ran logger.track_realization, track.csv. The shards may
// come in any order. Their scenario.json must be byte-identical, their seeds equal, their
// realizations disjoint and together exactly 0 ... N-1: anything else is an error naming the
// shard, never a table over fewer realizations.
#pragma once

#include <string>
#include <vector>

namespace rnav {

struct MergeResult {
  std::string kind;        ///< "landing" or "uav"
  long realizations = 0;   ///< N
  std::int64_t seed = 0;
};

/// Merge `shard_dirs` into out_dir (written atomically file by file: the statistics files of
/// the scenario's kind, realizations.csv, datalink.csv where the shards have one, track.csv
/// where the scenario asks for it, each CSV with its NAME.units.json as one run writes it, and
/// scenario.json). A shard's CSV whose header is not the one this build writes is refused.
/// Throws std::runtime_error / std::invalid_argument naming the shard folder.
MergeResult merge_shards(const std::vector<std::string>& shard_dirs, const std::string& out_dir);

}  // namespace rnav
