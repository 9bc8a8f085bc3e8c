// Options of the azimuth-only ensemble's statistics (UAV scenario section "logger"), with their
// keys and checks.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// The azimuth-only ensemble's statistics.
struct UavLoggerOptions {
  double eval_time_s = -1;      ///< [s] when summary.json's figures are taken; -1: after two orbits
  double diverge_pos_m = 50;    ///< [m] a run whose position error at eval_time exceeds this diverged
  /// [s] realizations.csv has, per realization and estimator, the first frame in each interval
  /// [k step, (k+1) step) of run time (and the frame summary.json uses); 0: every frame.
  double realizations_step_s = 1;
  /// track.csv (loggers/uav_track.hpp; drawn as geometry.png): this realization's geometry frame
  /// by frame, >= 0 and below the run's realization count; -1: no track.csv.
  long track_realization = 0;
};
/// Throws ConfigError (naming logger.track_realization) unless it is -1 or below n_realizations.
void check_track_realization(const UavLoggerOptions& o, long n_realizations);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(UavLoggerOptions& o, V& v) {
  v.num("eval_time_s", o.eval_time_s, -1, 1e6);
  v.num("diverge_pos_m", o.diverge_pos_m, 0.01, 1e6);
  v.num("realizations_step_s", o.realizations_step_s, 0, 1e6);
  v.integer("track_realization", o.track_realization, -1, 999999999);
}

}  // namespace options_io
}  // namespace rnav
