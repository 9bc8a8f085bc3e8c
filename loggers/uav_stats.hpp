// Ensemble statistics of the azimuth-only estimators: per frame time and estimator, RMSE of
// position and velocity, mean NEES (4 dof) and mean NIS (1 dof) with their 95 % chi-square
// bands for the number of runs, and the posterior Cramer-Rao bound (TmaPcrb) for the same
// truth, detections and noise; at the evaluation time (two orbits) the summary per estimator
// and the share of diverged runs. Sums are exact (ExactSum), so the outputs do not depend on the
// order realizations are added or shards (ensemble_state.json) are merged in.
#pragma once

#include "common/io/csv_columns.hpp"
#include "common/physics/exact_sum.hpp"

#include "estimators/uav_tma/tma_pcrb.hpp"
#include "common/physics/frames.hpp"
#include "loggers/uav_stats_setup.hpp"

#include <array>
#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rnav {

/// One estimate's errors against the truth.
struct TmaSample {
  std::int64_t utime = 0;
  std::string estimator;
  double pos_err2 = 0;   ///< [m^2] squared horizontal position error
  double vel_err2 = 0;   ///< [m^2/s^2] squared velocity error
  double nees = 0;       ///< e^T P^-1 e, 4 dof
  bool updated = false;
  double nis = 0;        ///< 1 dof when updated
  std::array<double, 4> err{};    ///< estimate minus truth: north, east [m], v_north, v_east [m/s]
  std::array<double, 4> sigma{};  ///< the estimator's own 1 sigma of the same (sqrt of P's diagonal)
};

/// One realization's data: samples, and per detection frame the Fisher information of the
/// bearing at the truth (for the PCRB), the first one as the prior.
struct TmaRealization {
  std::vector<TmaSample> samples;
  std::map<std::int64_t, tma::Mat4> info;  ///< utime -> H^T R^-1 H at the truth
  std::int64_t first_utime = -1;           ///< first detection (the estimators' initialisation)
  tma::Mat4 J0 = tma::Mat4::Zero();        ///< prior information at the first detection
  /// The true horizontal range from the UAV to the object over the realization's frames [m].
  double range_min_m = std::numeric_limits<double>::infinity(), range_max_m = 0, range_sum_m = 0;
  long range_n = 0;
  void add_range(double r_m) {
    range_min_m = std::min(range_min_m, r_m);
    range_max_m = std::max(range_max_m, r_m);
    range_sum_m += r_m;
    ++range_n;
  }
};

/// Per estimator, the index into r.samples of its last sample at or before eval_utime: the one
/// summary.json's figures use.
std::map<std::string, std::size_t> samples_at_eval(const TmaRealization& r, std::int64_t eval_utime);

/// 95 % band of the mean of n chi-square(dof) variables divided by... : [lo, hi] such that
/// n * mean ~ chi2(n dof) (Wilson-Hilferty approximation).
std::pair<double, double> chi2_mean_band(long n, int dof, double z = 1.959963984540054);

class UavStats {
 public:
  explicit UavStats(const UavStatsSetup& sc);
  /// Add one complete realization; `realization` is its index in the ensemble (each at most
  /// once; -1: the next after the highest so far).
  void add_realization(const TmaRealization& r, long realization = -1);
  long realizations() const { return n_; }
  /// Write uav_stats_time.csv (and uav_stats_time.units.json), summary.json, summary.txt and
  /// ensemble_state.json (state()) into dir (atomically renamed). realizations.csv is the
  /// logger's (streamed), not this class's.
  void write(const std::string& dir, std::int64_t seed) const;
  /// The same (the name PrlStats uses for "everything but realizations.csv").
  void write_statistics(const std::string& dir, std::int64_t seed) const { write(dir, seed); }
  /// uav_stats_time.csv's columns (its header and uav_stats_time.units.json), per estimator
  /// held (in name order).
  std::vector<CsvColumnDoc> stats_time_columns() const;
  /// The PCRB position RMSE [m] per frame time (utime -> value), computed from the ensemble.
  std::map<std::int64_t, double> pcrb_pos() const;
  std::map<std::int64_t, double> pcrb_vel() const;

  struct Acc {
    long n = 0, n_upd = 0;
    ExactSum pos2, vel2, nees, nis;
  };
  struct FinalAcc {
    long n = 0, diverged = 0;
    ExactSum pos2, vel2, nees;
  };
  const std::map<std::string, FinalAcc>& at_eval() const { return final_; }

  /// The exact state (every sum as ExactSum text) and the realizations it holds: what merging
  /// shards needs (written as ensemble_state.json by write()).
  nlohmann::ordered_json state(std::int64_t seed) const;
  /// Add a shard's state (of other realizations of the same scenario and seed): the result
  /// equals adding those realizations here, whatever the order of shards. Throws
  /// std::invalid_argument naming `what` on a malformed state, another seed or a realization
  /// present in both; nothing is added then.
  void merge_state(const nlohmann::json& state, std::int64_t seed, const std::string& what);
  /// The realizations held, by index.
  const std::set<long>& realization_set() const { return held_; }

 private:
  void pcrb(std::map<std::int64_t, double>* pos, std::map<std::int64_t, double>* vel) const;
  UavStatsSetup sc_;
  long n_ = 0;
  std::map<std::string, std::map<std::int64_t, Acc>> by_time_;
  std::map<std::string, FinalAcc> final_;
  using MatSum = std::array<ExactSum, 16>;  // a 4x4 matrix's exact sum, column-major
  static void add_to(MatSum& s, const tma::Mat4& m);
  static tma::Mat4 value(const MatSum& s);
  std::map<std::int64_t, MatSum> info_sum_;
  MatSum J0_sum_;
  std::int64_t first_utime_ = -1;
  std::vector<std::int64_t> frames_;  // all frame times seen
  std::set<long> held_;               // the realizations added
  // True UAV-object range over all frames of all realizations [m]; runs whose object stayed
  // inside the orbit (range <= 2 uav.radius_m at every frame: the object within the orbit's disc).
  double range_min_m_ = std::numeric_limits<double>::infinity(), range_max_m_ = 0;
  ExactSum range_sum_m_;
  long range_n_ = 0, inside_orbit_runs_ = 0;
};

}  // namespace rnav
