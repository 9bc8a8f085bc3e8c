// Approaches in a cleaned ADS-B track, their statistics, and their export as a replay CSV.
//
// Course at kept point i: the geodesic azimuth from point i-1 to point i+1 (one-sided at the
// ends); the point is ON COURSE when |course - runway heading| <= course_tolerance_deg. An
// APPROACH is a maximal run of consecutive on-course points (no time step above max_gap_s)
// cut at the run's lowest point (the go-around or the landing) and kept when it descends at
// least min_descent_m from its first point to that lowest point and lasts min_duration_s.
//
// Height. ADS-B altitude is barometric, referenced to 1013.25 hPa: it differs from height
// above the WGS84 ellipsoid by an offset made of the day's QNH (about 8.3 m per hPa) and the
// geoid undulation (about 45 m at Vienna), neither of which the data carries. We use
//   h_m = height_ft * 0.3048 + offset_m,
// with offset_m either given (--height-offset-m) or, by default, FITTED per approach: a
// straight line y = a + b x is fitted (least squares) in the landing frame L to the points of
// the middle 80 % of the approach's descent (heights between h_low + 0.1 D and h_start - 0.1 D,
// D = the descent: away from the level leg before the glide path and the level-off at the
// bottom), and offset_m = glide_path_tch_m - a, so that the fitted glide path crosses the
// threshold at glide_path_tch_m (default 15 m = 50 ft, ICAO's ILS reference datum height).
// The offset is a height shift: it cannot change the glide angle b, which is reported.
#pragma once

#include "sim/trajectory/adsb_glitches.hpp"
#include "common/io/csv_columns.hpp"
#include "common/physics/frames.hpp"

#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace rnav {

struct ApproachSearchOptions {
  Geodetic threshold{48.10153, 16.58495, 228.0};  ///< runway threshold (origin of L); default: our scenario's LOWW 29
  double heading_deg = 295.9;          ///< [deg] landing true heading, [0, 360)
  double course_tolerance_deg = 15;    ///< [deg] on-course half-width, (0, 90]
  double min_descent_m = 150;          ///< [m] least descent from the run's start to its lowest point, > 0
  double min_duration_s = 60;          ///< [s] least duration of an approach, > 0
  double max_gap_s = 30;               ///< [s] a longer time step between kept points ends a run, > 0
  double glide_path_tch_m = 15;        ///< [m] height of the fitted glide path over the threshold
  std::optional<double> height_offset_m;  ///< [m] fixed offset instead of the fit
  HeightSource height = HeightSource::baro;
};

struct Approach {
  std::size_t first = 0, last = 0;  ///< indices into the kept points: first point, lowest point
  double t_start_s = 0, t_end_s = 0;     ///< [s] since the Unix epoch
  double h_start_ft = 0, h_min_ft = 0;   ///< [ft] the chosen height, at the start and lowest
  double dist_start_m = 0, dist_end_m = 0;  ///< [m] horizontal geodesic distance to the threshold
  double x_start_m = 0, x_end_m = 0;     ///< [m] along the runway axis in L (positive: before the threshold)
  double lateral_mean_m = 0;  ///< [m] mean z in L: offset of the flown line from the centreline through the threshold
  double lateral_rms_m = 0;   ///< [m] RMS of z about that mean: how well the approach holds one line
  std::optional<double> glide_deg;       ///< [deg] fitted glide angle (atan b), if >= 5 points to fit
  std::optional<double> fitted_offset_m; ///< [m] offset placing the fit at glide_path_tch_m over the threshold
  double offset_m = 0;  ///< [m] the offset the export uses (given, else fitted; NaN if neither)
};

/// Find the approaches in the kept points of a cleaned track.
std::vector<Approach> find_approaches(const std::vector<AdsbRecord>& kept, const ApproachSearchOptions& o);

/// The --list table (one line per approach, 1-based index).
void print_approach_table(std::ostream& os, const std::vector<Approach>& a);

/// What write_replay_csv writes of an approach.
struct ReplayExportOptions {
  double lead_s = 0;  ///< [s] also the kept points up to this long before the approach's start, >= 0
  /// [m] stop before the first point (after the start) whose x in L is below this, e.g. 0 = at
  /// the threshold, so that a replay does not fly past a radar beside the runway; default: no
  /// limit (to the lowest point)
  double end_x_m = -std::numeric_limits<double>::infinity();
};

/// The replay CSV's columns (unit and meaning of each).
std::vector<CsvColumnDoc> replay_csv_columns();

/// Write approach `a` as a replay CSV (t_s,lat_deg,lon_deg,h_m; t_s from the first written
/// row; h_m = height_ft * 0.3048 + a.offset_m) and its description beside it (FILE without .csv
/// + ".units.json", csv_columns.hpp). Returns the number of rows. Throws ConfigError
/// if the file cannot be written, no height offset is available or fewer than 3 rows remain.
std::size_t write_replay_csv(const std::string& file, const std::vector<AdsbRecord>& kept,
                             const Approach& a, const ApproachSearchOptions& o,
                             const ReplayExportOptions& e);

}  // namespace rnav
