#include "loggers/uav_logger_options.hpp"

namespace rnav {

void check_track_realization(const UavLoggerOptions& o, long n_realizations) {
  if (o.track_realization >= n_realizations)
    throw ConfigError("scenario key 'logger.track_realization' = " + std::to_string(o.track_realization) +
                      " names no realization of this run (0 ... " + std::to_string(n_realizations - 1) +
                      "; -1: no track.csv)");
}

}  // namespace rnav
