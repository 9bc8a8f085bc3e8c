// Ensemble statistics of the landing-radar simulation (no I/O besides writing results).
//
// For every plot: the position error in the landing frame L of the raw plot (APOI) and of the
// compensated plot (TOI), e = p_plot_L - p_true_L, components X, Z, Y; and the bias-estimate
// error eta_hat - (radar systematic error) per polar channel. Over the ensemble:
//   - per plot time: mean (systematic) and RMS of each component;
//   - per slant-range bin: the same over all plots in the bin;
//   - Table 2: per realization the mean error over the plots within +-halfwidth of each table
//     range, then the ensemble mean of those, its standard error s/sqrt(N) and 95 % band.
// Realizations are added in order, so sums (and outputs) are deterministic.
#pragma once

#include "scenario.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav {

/// One plot's errors in one realization.
struct PlotErrors {
  std::int64_t utime = 0;
  double range_true_m = 0;          ///< [m] true slant range from the radar
  double range_table_m = 0;         ///< [m] true range in the sense of logger.table_range_origin
  std::array<double, 3> apoi{};     ///< [m] raw plot error in L: X, Z, Y
  std::array<double, 3> toi{};      ///< [m] compensated plot error in L: X, Z, Y
  std::array<double, 3> p_true_L{};  ///< [m] true aircraft position in L: x, y, z (the same in every realization)
  std::array<double, 3> bias_err{}; ///< eta_hat - radar systematic error [m, rad, rad]
  std::array<double, 3> bias_var{}; ///< the filter's variance p [m^2, rad^2, rad^2]
  int mode = 0;                     ///< prl_bias_estimate_t mode
};

/// Running sums of a vector quantity.
template <int N> struct Moments {
  long n = 0;
  std::array<double, N> sum{}, sumsq{};
  void add(const std::array<double, N>& x) {
    ++n;
    for (int i = 0; i < N; ++i) {
      sum[i] += x[i];
      sumsq[i] += x[i] * x[i];
    }
  }
  double mean(int i) const { return n ? sum[i] / n : 0; }
  double rms(int i) const { return n ? std::sqrt(sumsq[i] / n) : 0; }
  /// Sample standard deviation (n - 1).
  double sd(int i) const {
    if (n < 2) return 0;
    const double v = (sumsq[i] - sum[i] * sum[i] / n) / (n - 1);
    return v > 0 ? std::sqrt(v) : 0;
  }
};

/// Paper's Table 2 (method.md): APOI and TOI systematic error [m], X Z Y, at 25 km and 4 km.
struct PaperTable2 {
  static bool has(double range_m);
  static std::array<double, 3> apoi(double range_m);
  static std::array<double, 3> toi(double range_m);
};

class PrlStats {
 public:
  explicit PrlStats(const Scenario& sc);
  /// Add one complete realization (plots in time order).
  void add_realization(const std::vector<PlotErrors>& plots);
  long realizations() const { return n_real_; }

  /// Write stats_time.csv, stats_range.csv, realizations.csv, table2.json, table2_detail.json and table2.txt
  /// into dir. `seed` is recorded. Files are written under temporary names and renamed.
  void write(const std::string& dir, std::int64_t seed) const;
  /// Table 2 text (also written to table2.txt).
  std::string table2_text(std::int64_t seed) const;

  struct TimeBin {
    double range_true_m = 0, range_table_m = 0;
    std::array<double, 3> p_true_L{};  // [m] x, y, z
    Moments<3> apoi, toi, bias_err, bias_var;
  };
  const std::map<std::int64_t, TimeBin>& by_time() const { return by_time_; }
  const std::vector<Moments<3>>& table_apoi() const { return table_apoi_; }
  const std::vector<Moments<3>>& table_toi() const { return table_toi_; }

 private:
  Scenario sc_;
  long n_real_ = 0;
  std::map<std::int64_t, TimeBin> by_time_;
  std::map<long, std::pair<Moments<3>, Moments<3>>> by_range_;  // bin index -> (apoi, toi)
  std::vector<Moments<3>> table_apoi_, table_toi_;               // per table range
  std::vector<long> table_plots_;                                 // plots per bin per realization
  std::string realization_rows_;                                  // realizations.csv, without its header
};

}  // namespace rnav
