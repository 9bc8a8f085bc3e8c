// Node "uav_logger": joins TRUTH_TARGET, TRUTH_UAV, UAV_BEARING and UAV_TMA per frame, keeps a
// realization until the clock moves past it, adds it to UavStats and its rows to
// realizations.csv (uav_realizations.hpp; written as it goes, renamed into place on FINISH);
// keeps realization logger.track_realization's geometry for track.csv (uav_track.hpp);
// writes the results and scenario.json on FINISH, each CSV with its NAME.units.json
// (ensemble_logger_node.hpp).
// An estimate without truth at its time, or an ensemble short of realizations, is an error.
#pragma once

#include "common/io/atomic_file.hpp"
#include "loggers/ensemble_logger_node.hpp"
#include "loggers/uav_stats.hpp"
#include "loggers/uav_track.hpp"

#include <Eigen/Dense>

#include <map>
#include <memory>

namespace rnav {

class UavLoggerNode : public EnsembleLoggerNode<UavStats, TmaRealization> {
 public:
  /// @param scenario_json  the effective scenario's text, written as scenario.json
  /// @param out_dir        where FINISH writes the result files; "" writes nothing
  UavLoggerNode(Bus& bus, const UavStatsSetup& sc, std::string scenario_json, std::string out_dir);

 protected:
  void start_realization(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;
  void committed() override;
  void write_own(const sim_window_t& w) override;

 private:
  UavStatsSetup sc_;
  std::unique_ptr<AtomicFileWriter> rows_;  // realizations.csv, a realization's rows at each commit
  bool tracking_ = false;   // the realization being assembled is logger.track_realization
  UavTrack track_;          // its frames
  std::string track_csv_;   // track.csv's text once that realization is committed
  std::vector<CsvColumnDoc> track_columns_;  // and its columns (track.units.json)
};

}  // namespace rnav
