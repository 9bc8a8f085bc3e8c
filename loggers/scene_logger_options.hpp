// Options of a recorded scene run's logger (scene scenario section "logger"), with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

struct SceneLoggerOptions {
  /// Realizations 0 ... recordings-1 of the run are each written as a recording folder
  /// realization_NNNNNN/ (observer.csv, detections.csv, truth.csv, targets.csv: the format
  /// scripts/diagnose multi reads), [0, 100000]. Every realization counts in summary.json.
  long recordings = 1;
};

namespace options_io {

template <class V> void visit(SceneLoggerOptions& o, V& v) { v.integer("recordings", o.recordings, 0, 100000); }

}  // namespace options_io
}  // namespace rnav
