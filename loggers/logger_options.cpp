#include "loggers/logger_options.hpp"

namespace rnav {

void check_logger(const LoggerOptions& o) {
  if (o.table_ranges_m.empty())
    throw ConfigError("scenario key 'logger.table_ranges_m' must list at least one range");
}

}  // namespace rnav
