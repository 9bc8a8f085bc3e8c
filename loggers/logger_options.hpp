// Options of the landing ensemble's statistics (scenario section "logger"), with their keys and checks.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// Ensemble statistics.
struct LoggerOptions {
  std::vector<double> table_ranges_m{25000, 4000};  ///< [m] Table 2 ranges (see table_range_origin)
  /// What a Table 2 "range" is measured from: "radar" (true slant range from the radar antenna)
  /// or "threshold" (true distance from the runway threshold). The paper does not say; its
  /// APOI values fit "threshold" (see README, "The paper scenario and our choices").
  std::string table_range_origin = "radar";
  double table_halfwidth_m = 250;  ///< [m] plots within +- this of a table range form its bin
  double range_bin_m = 1000;       ///< [m] width of the range bins of stats_range.csv
};
/// Throws ConfigError (naming logger.table_ranges_m) unless it lists at least one range.
void check_logger(const LoggerOptions& o);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(LoggerOptions& o, V& v) {
  v.list("table_ranges_m", o.table_ranges_m, 0, 1e6);
  v.num("table_halfwidth_m", o.table_halfwidth_m, 1, 1e5);
  v.choice("table_range_origin", o.table_range_origin, {"radar", "threshold"});
  v.num("range_bin_m", o.range_bin_m, 10, 1e5);
}

}  // namespace options_io
}  // namespace rnav
