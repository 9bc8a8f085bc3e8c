// Options of the aircraft's true path (scenario section "trajectory"), with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// Aircraft path in L (paper: start x = 30860 m, z = 9860 m, y = 400 m; level, then 2 deg 40').
/// Lateral path: a straight leg from the start towards the centreline point (intercept_x_m, 0),
/// a coordinated turn at bank_deg onto the centreline, then straight in. Constant ground speed.
struct TrajectoryOptions {
  double start_x_m = 30860;   ///< [m] paper
  double start_y_m = 400;     ///< [m] paper; also the level-leg height in L
  double start_z_m = 9860;    ///< [m] paper
  double speed_mps = 75;      ///< [m/s] horizontal ground speed (our choice: a military approach speed), [10, 300]
  double intercept_x_m = 27000;  ///< [m] where the first leg would cross the centreline (our choice)
  double bank_deg = 25;       ///< [deg] bank angle of the turn onto final (our choice), [1, 60]
  double glide_deg = 2.0 + 40.0 / 60.0;  ///< [deg] descent angle 2 deg 40' (paper), (0, 10]
  double aim_x_m = -300;      ///< [m] where the glide path meets y = 0 (our choice: touchdown zone)
  double end_x_m = 0;         ///< [m] the run ends when the aircraft reaches this x on final
  double step_s = 0.25;       ///< [s] truth sample step; radar and nav sample times lie on this grid
  /// Replay a recorded approach instead of the analytic path above: a CSV file with columns
  /// t_s,lat_deg,lon_deg,h_m (time [s], strictly increasing; WGS84 latitude and longitude
  /// [deg]; height above the WGS84 ellipsoid [m]), e.g. written by rnav_import_adsb. Its first
  /// row is sim time 0 and its last row ends the run. "" (default) = the analytic path, and the
  /// keys above except step_s are then the only geometry. A relative path is relative to the
  /// scenario file's directory (relative to the working directory when it comes from --set).
  std::string replay_csv;
  /// [s] half-width W of the replay's smoothing window: position and velocity at t are those
  /// of a least-squares quadratic in time fitted to the samples within |t_i - t| < W, weighted
  /// (1 - |t_i - t|^3 / W^3)^3. Larger W: less ADS-B noise, more rounded turns. [1, 300];
  /// must exceed 2 * the largest time step of the file (at least 3 samples in every window).
  double replay_smoothing_s = 30;
  /// [s] largest time step allowed between consecutive rows of replay_csv (a longer gap is an
  /// error naming the line: the replay would invent the path across it), (0, 120]
  double replay_max_gap_s = 15;
};

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(TrajectoryOptions& o, V& v) {
  v.num("start_x_m", o.start_x_m, 1000, 200000);
  v.num("start_y_m", o.start_y_m, 10, 15000);
  v.num("start_z_m", o.start_z_m, -100000, 100000);
  v.num("speed_mps", o.speed_mps, 10, 300);
  v.num("intercept_x_m", o.intercept_x_m, 0, 200000);
  v.num("bank_deg", o.bank_deg, 1, 60);
  v.num("glide_deg", o.glide_deg, 0.5, 10);
  v.num("aim_x_m", o.aim_x_m, -5000, 5000);
  v.num("end_x_m", o.end_x_m, -5000, 50000);
  v.num("step_s", o.step_s, 0.01, 10);
  v.str("replay_csv", o.replay_csv);
  v.num("replay_smoothing_s", o.replay_smoothing_s, 1, 300);
  v.num("replay_max_gap_s", o.replay_max_gap_s, 1e-3, 120);
}

}  // namespace options_io
}  // namespace rnav
