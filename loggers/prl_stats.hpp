// Ensemble statistics of the landing-radar simulation (no I/O besides writing results).
//
// For every plot: the position error in the landing frame L of the raw plot (APOI) and of the
// compensated plot (TOI), e = p_plot_L - p_true_L, components X, Z, Y; and the bias-estimate
// error eta_hat - (radar systematic error) per polar channel. Over the ensemble:
//   - per plot time: mean (systematic) and RMS of each component;
//   - per slant-range bin: the same over all plots in the bin;
//   - Table 2: per realization the mean error over the plots within +-halfwidth of each table
//     range, then the ensemble mean of those, its standard error s/sqrt(N) and 95 % band.
// Sums are exact (ExactSum) and rounded once when read, so the outputs do not depend on the
// order realizations are added in: an ensemble run in shards (realization ranges, e.g. on MPI
// ranks) whose states (ensemble_state.json) are merged in any order writes the same bytes as
// one run of the whole ensemble.
#pragma once

#include "common/io/csv_columns.hpp"
#include "common/physics/exact_sum.hpp"
#include "loggers/logger_options.hpp"
#include "common/node/site_context.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
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

/// A plain running double sum, for sums that are always made in one fixed order (within one
/// realization): the ExactSum interface without its cost.
struct PlainSum {
  double s = 0;
  void add(double x) { s += x; }
  void merge(const PlainSum& o) { s += o.s; }
  double value() const { return s; }
};

/// Running sums of a vector quantity, held exactly by default (ExactSum: order-independent,
/// mergeable); with Sum = PlainSum for sums within one realization.
template <int N, class Sum = ExactSum> struct Moments {
  long n = 0;
  std::array<Sum, N> sum{}, sumsq{};
  void add(const std::array<double, N>& x) {
    ++n;
    for (int i = 0; i < N; ++i) {
      sum[i].add(x[i]);
      sumsq[i].add(x[i] * x[i]);
    }
  }
  /// The moments of both samples together (exact: the same as adding o's values here).
  void merge(const Moments& o) {
    n += o.n;
    for (int i = 0; i < N; ++i) {
      sum[i].merge(o.sum[i]);
      sumsq[i].merge(o.sumsq[i]);
    }
  }
  double mean(int i) const { return n ? sum[i].value() / n : 0; }
  double rms(int i) const { return n ? std::sqrt(sumsq[i].value() / n) : 0; }
  /// Sample standard deviation (n - 1).
  double sd(int i) const {
    if (n < 2) return 0;
    const double s = sum[i].value();
    const double v = (sumsq[i].value() - s * s / n) / (n - 1);
    return v > 0 ? std::sqrt(v) : 0;
  }
  /// Exact state: {"n": n, "sum": [text...], "sumsq": [text...]} (ExactSum::to_text).
  nlohmann::ordered_json state() const {
    nlohmann::ordered_json j{{"n", n}, {"sum", nlohmann::ordered_json::array()}, {"sumsq", nlohmann::ordered_json::array()}};
    for (int i = 0; i < N; ++i) {
      j["sum"].push_back(sum[i].to_text());
      j["sumsq"].push_back(sumsq[i].to_text());
    }
    return j;
  }
  /// Inverse of state(); throws std::invalid_argument naming `what` on a malformed state.
  static Moments from_state(const nlohmann::json& j, const std::string& what) {
    Moments m;
    if (!j.is_object() || !j.contains("n") || !j["n"].is_number_integer() || j["n"].get<long>() < 0 ||
        !j.contains("sum") || !j.contains("sumsq") || !j["sum"].is_array() || !j["sumsq"].is_array() ||
        j["sum"].size() != N || j["sumsq"].size() != N)
      throw std::invalid_argument(what + ": expected {\"n\": count, \"sum\": [" + std::to_string(N) +
                                  " sums], \"sumsq\": [" + std::to_string(N) + " sums]}");
    m.n = j["n"].get<long>();
    for (int i = 0; i < N; ++i) {
      if (!j["sum"][i].is_string() || !j["sumsq"][i].is_string()) throw std::invalid_argument(what + ": sums must be strings");
      m.sum[i] = ExactSum::from_text(j["sum"][i].get<std::string>(), what + ".sum[" + std::to_string(i) + "]");
      m.sumsq[i] = ExactSum::from_text(j["sumsq"][i].get<std::string>(), what + ".sumsq[" + std::to_string(i) + "]");
    }
    return m;
  }
};

/// Paper's Table 2 (docs/method.md): APOI and TOI systematic error [m], X Z Y, at 25 km and 4 km.
struct PaperTable2 {
  static bool has(double range_m);
  static std::array<double, 3> apoi(double range_m);
  static std::array<double, 3> toi(double range_m);
};

class PrlStats {
 public:
  PrlStats(const LoggerOptions& o, const SiteContext& site);
  /// Add one complete realization (plots in time order). `realization`: its index in the
  /// ensemble (realizations.csv's first column; each index at most once); -1: the next after
  /// the highest so far (0 for the first).
  void add_realization(const std::vector<PlotErrors>& plots, long realization = -1);
  long realizations() const { return n_real_; }

  /// Write write_statistics()'s files and realizations.csv into dir. `seed` is recorded. Files
  /// are written under temporary names and renamed.
  void write(const std::string& dir, std::int64_t seed) const;
  /// Write stats_time.csv, stats_range.csv, table2.json, table2_detail.json, table2.txt and
  /// ensemble_state.json (state()): everything but the per-realization rows (which a merge of
  /// shards takes from the shards' realizations.csv files). Each CSV with its NAME.units.json.
  void write_statistics(const std::string& dir, std::int64_t seed) const;

  /// The exact state (every sum as ExactSum text, the realizations held): what a merge needs.
  nlohmann::ordered_json state(std::int64_t seed) const;
  const std::set<long>& realization_set() const { return held_; }
  /// Add a shard's state (state() of a run of other realizations of the same scenario and seed)
  /// to this one. The result equals adding those realizations here, whatever the order of
  /// shards. Throws std::invalid_argument naming `what` on a malformed state, another seed, or a
  /// realization present in both.
  void merge_state(const nlohmann::json& state, std::int64_t seed, const std::string& what);
  /// Table 2 text (also written to table2.txt).
  std::string table2_text(std::int64_t seed) const;

  /// The columns of realizations.csv, stats_time.csv and stats_range.csv (unit and meaning of
  /// each; the files' headers and their NAME.units.json beside them come from these lists).
  std::vector<CsvColumnDoc> realizations_columns() const;
  std::vector<CsvColumnDoc> stats_time_columns() const;
  std::vector<CsvColumnDoc> stats_range_columns() const;

  struct TimeBin {
    double range_true_m = 0, range_table_m = 0;
    std::array<double, 3> p_true_L{};  // [m] x, y, z
    Moments<3> apoi, toi, bias_err, bias_var;
  };
  const std::map<std::int64_t, TimeBin>& by_time() const { return by_time_; }
  const std::vector<Moments<3>>& table_apoi() const { return table_apoi_; }
  const std::vector<Moments<3>>& table_toi() const { return table_toi_; }

 private:
  std::string all_rows() const;  // realizations.csv's rows, in realization order
  LoggerOptions logger_;
  SiteContext site_;
  long n_real_ = 0;
  std::map<std::int64_t, TimeBin> by_time_;
  std::map<long, std::pair<Moments<3>, Moments<3>>> by_range_;  // bin index -> (apoi, toi)
  std::vector<Moments<3>> table_apoi_, table_toi_;               // per table range
  std::vector<long> table_plots_;                                 // plots per bin per realization
  std::map<long, std::string> realization_rows_;                  // realization -> its realizations.csv rows
  std::set<long> held_;                                           // realizations added (or merged)
};

}  // namespace rnav
