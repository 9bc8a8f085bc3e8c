// realizations.csv of the azimuth-only ensemble: one row per realization, estimator and time
// step (the first frame of each logger.realizations_step_s interval, default 1 s; 0: every
// frame), plus the frame
// summary.json takes its figures from (at_eval = 1; the last frame at or before
// logger.eval_time_s). Per row: the estimate's error (estimate minus truth: north, east [m],
// v_north, v_east [m/s]) and its norms, the estimator's own 1 sigma of each component (square
// root of its covariance's diagonal), NEES, whether a bearing was used, and NIS.
// So: summary.json's rmse_pos_m is the RMS of pos_err_m over the at_eval rows of an estimator,
// nees_mean their mean NEES, diverged the count with pos_err_m > logger.diverge_pos_m (or not
// finite); uav_stats_time.csv's RMSE at a time is the RMS over that time's rows (times on the step grid).
#pragma once

#include "common/io/csv_columns.hpp"
#include "loggers/uav_stats.hpp"

#include <string>
#include <vector>

namespace rnav {

/// The file's columns: unit and meaning of each; the header line is csv_header() of them and
/// realizations.units.json describes them.
std::vector<CsvColumnDoc> uav_realizations_columns();
/// The rows of one realization, ordered by estimator and time, each ending in a newline.
std::string uav_realization_rows(const UavStatsSetup& sc, long realization, const TmaRealization& r);

}  // namespace rnav
