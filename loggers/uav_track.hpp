// track.csv of the azimuth-only run: one realization's geometry frame by frame (the one named by
// logger.track_realization, default 0), for the plan view geometry.png (scripts/plot_uav.py).
// One row per frame of TRUTH_TARGET, in time order:
//   realization, t_s (run time, 6 decimals: the frame's exact microsecond),
//   uav_north_m, uav_east_m                      the UAV's true position,
//   object_north_m, object_east_m, object_v_north_mps, object_v_east_mps   the object's truth,
//   n_bearings                                   bearings measured at this frame (0, 1, ...),
//   bearing_rad                                  the first of them (as received), clockwise from
//                                                north; "nan" when n_bearings = 0,
// and per estimator NAME (UAV_TMA's `estimator`, in name order):
//   NAME_north_m, NAME_east_m, NAME_v_north_mps, NAME_v_east_mps   its estimate,
//   NAME_P_nn_m2, NAME_P_ne_m2, NAME_P_ee_m2     its 2x2 position covariance (north, east; the
//                                                off-diagonal is the mean of P's two, so the
//                                                2x2 is symmetric by construction);
//   all "nan" at a frame without an estimate of NAME (before its first bearing).
// Numbers other than t_s with 9 significant digits (%.9g: relative rounding <= 5e-9).
// Everything comes from messages, so the file is the same whatever the transport.
#pragma once

#include "common/io/csv_columns.hpp"
#include "estimators/uav_tma/tma_models.hpp"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav {

class UavTrack {
 public:
  void clear() { frames_.clear(); }
  /// The object's true state x = (north, east [m], v_north, v_east [m/s]) at utime.
  void add_object(std::int64_t utime, const tma::Vec4& x);
  /// The UAV's true position (north, east) [m] at utime.
  void add_uav(std::int64_t utime, const Eigen::Vector2d& p);
  /// A bearing [rad] measured at utime (the first of a frame is written, all are counted).
  void add_bearing(std::int64_t utime, double bearing_rad);
  /// An estimate of `estimator` at utime: state and 4x4 covariance (UAV_TMA). A second one of
  /// the same estimator and utime is an error.
  void add_estimate(std::int64_t utime, const std::string& estimator, const tma::Vec4& x, const tma::Mat4& P);
  /// The file's text (header and rows). Throws if a frame lacks the object's or the UAV's truth
  /// (naming the utime and channel).
  std::string csv(std::int64_t epoch_utime, long realization) const;
  /// The estimators seen so far, in name order (the file's estimator column groups).
  std::vector<std::string> estimators() const;
  /// The file's columns for these estimators (in this order): unit and meaning of each, the
  /// header and track.units.json.
  static std::vector<CsvColumnDoc> columns(const std::vector<std::string>& estimators);
  /// The columns of a track.csv whose header line is `header` (the estimators read from it);
  /// throws std::runtime_error naming `what` unless the header is exactly one this code writes.
  static std::vector<CsvColumnDoc> columns_of_header(const std::string& header, const std::string& what);

 private:
  struct Estimate {
    tma::Vec4 x;
    double P_nn = 0, P_ne = 0, P_ee = 0;  ///< [m^2]
  };
  struct Frame {
    bool has_object = false, has_uav = false;
    tma::Vec4 object = tma::Vec4::Zero();
    Eigen::Vector2d uav = Eigen::Vector2d::Zero();
    int n_bearings = 0;
    double bearing_rad = NAN;
    std::map<std::string, Estimate> est;
  };
  std::map<std::int64_t, Frame> frames_;
};

}  // namespace rnav
