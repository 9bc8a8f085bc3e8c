// The bookkeeping both loggers share (the landing logger, "logger", and the UAV logger,
// "uav_logger"): a realization is assembled from the windows of its current attempt (a repeated
// attempt starts it afresh), added to the ensemble's statistics once the clock moves past it
// (commit), and on FINISH, if the statistics hold exactly the realizations the clock ran, the
// result files are written: the statistics', the logger's own, and scenario.json. The logger
// supplies the joining (process) and what it keeps or writes beyond the statistics.
#pragma once

#include "common/io/atomic_file.hpp"
#include "common/node/lockstep_node.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace rnav {

/// Stats: the ensemble statistics (add_realization(const Realization&, long), realizations(),
/// write(dir, seed)); Realization: what one realization adds to them.
template <class Stats, class Realization> class EnsembleLoggerNode : public LockstepNode {
 public:
  /// The ensemble's statistics over the realizations committed so far.
  const Stats& stats() const { return stats_; }

 protected:
  /// @param name            the node's name ("logger", "uav_logger")
  /// @param peer_timeout_s  [s wall] runner.peer_timeout_s
  /// @param stats           the (empty) statistics
  /// @param scenario_json   the effective scenario's text (the composed scenario's print), written as scenario.json
  /// @param out_dir         where FINISH writes the result files; "" writes nothing
  EnsembleLoggerNode(Bus& bus, std::string name, double peer_timeout_s, Stats stats, std::string scenario_json,
                     std::string out_dir)
      : LockstepNode(bus, std::move(name), peer_timeout_s), out_dir_(std::move(out_dir)),
        stats_(std::move(stats)), scenario_json_(std::move(scenario_json)) {}

  void reset(const sim_window_t& w) final {
    seed_ = w.seed;
    realization_ = w.realization;
    current_ = Realization{};
    start_realization(w);
  }
  void commit() final {
    stats_.add_realization(current_, realization_);
    committed();
    current_ = Realization{};
  }
  void finish(const sim_window_t& w) final {
    if (stats_.realizations() != w.n_realizations)
      throw std::runtime_error(name() + " holds " + std::to_string(stats_.realizations()) +
                               " complete realizations, the clock ran " + std::to_string(w.n_realizations));
    if (out_dir_.empty()) return;
    stats_.write(out_dir_, seed_);
    write_own(w);
    // The effective scenario, every default filled in and the overrides applied: `scripts/run
    // DIR/scenario.json` with the same seed and realizations repeats the run.
    write_file_atomic(out_dir_, "scenario.json", scenario_json_);
  }

  /// A realization (or a repeated attempt of it) begins: drop what the logger kept of the last.
  virtual void start_realization(const sim_window_t& w) = 0;
  /// The current realization has just been added to the statistics (current_ still holds it).
  virtual void committed() {}
  /// FINISH, after the statistics' files: write the logger's own files into out_dir_.
  virtual void write_own(const sim_window_t& /*finish*/) {}

  std::string out_dir_;  ///< "" writes nothing
  Realization current_;  ///< the realization being assembled
  long realization_ = 0; ///< its index in the ensemble

 private:
  Stats stats_;
  std::string scenario_json_;
  std::int64_t seed_ = 0;
};

}  // namespace rnav
