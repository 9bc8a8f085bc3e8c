// Multi-sensor, multi-target observation data in a CSV interchange format: one folder with
//   observer.csv    t_s,lat_deg,lon_deg,h_m[,heading_deg]
//                   the observer's (ownship's) navigation solution, WGS84, h_m above the
//                   ellipsoid; t_s strictly increasing; heading_deg optional column, clockwise
//                   from true north in [0, 360), cells may be empty (unknown).
//   detections.csv  t_s,sensor,range_m,bearing_deg[,elevation_deg]
//                   one row per detection. sensor: [a-z0-9_]+ (radar, lidar, eo, ir, ...).
//                   range_m: empty for bearing-only sensors, else in [0, 1e6]. bearing_deg:
//                   true bearing observer -> detection, clockwise from north, [-360, 360].
//                   elevation_deg: optional column, cells may be empty, [-90, 90]. range_m and
//                   bearing_deg both empty: a scan of that sensor without detection. Rows of one
//                   sensor in non-decreasing t_s (one t_s = one scan); sensors may interleave.
//   truth.csv       optional file: t_s,target,lat_deg,lon_deg[,h_m]
//                   each target's reference track; target: [A-Za-z0-9_]+; per target t_s
//                   strictly increasing; h_m optional column, cells may be empty.
//   targets.csv     optional file: target,length_m,beam_m
//                   each target's hull size as its AIS static data give it (length = A + B,
//                   beam = C + D); cells may be empty, and 0 (AIS: not available) is unknown;
//                   a target at most once; targets without a row are of unknown size.
// Times are in one time scale for all files (e.g. Unix seconds, UTC). Headers are required,
// extra columns ignored; every violation is a ConfigError naming file:line and the column.
#pragma once

#include "common/io/csv_columns.hpp"
#include "common/physics/frames.hpp"

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace rnav {

/// One detection (or one empty scan) of one sensor, seen from the observer.
struct Detection {
  double t_s = 0;           ///< time of the scan [s], the observer's time scale
  std::string sensor;       ///< sensor name, [a-z0-9_]+
  double range_m = 0;       ///< range observer -> detection [m], >= 0; NaN for bearing-only sensors and empty scans
  double bearing_rad = 0;   ///< true bearing observer -> detection [rad], clockwise from north, (-pi, pi]; NaN for an empty scan
  double elevation_rad = 0; ///< elevation above the observer's horizontal [rad], [-pi/2, pi/2]; NaN if none
  /// True for a row that records a scan without detection.
  bool empty_scan() const;
};

/// A target's hull size [m] (NaN: unknown), e.g. from its AIS static data.
struct HullSize {
  double length_m = NAN;
  double beam_m = NAN;
};

struct MultiSensorData {
  std::vector<GeoSample> observer;           ///< observer's position, t_s strictly increasing
  std::vector<double> observer_heading_deg;  ///< observer's heading at observer[i].t_s [deg], clockwise from true north, [0, 360); NaN where absent. Same length as observer (write_folder also accepts it empty: no heading)
  std::vector<Detection> detections;         ///< file order: per sensor non-decreasing t_s
  std::map<std::string, std::vector<GeoSample>> truth;  ///< per target name, t_s strictly increasing; h_m NaN where unknown; empty without truth.csv
  std::map<std::string, HullSize> hull;  ///< per target name with a targets.csv row; empty without targets.csv
  /// The detections are a simulation's (sim/scene), held in memory: their units are ours, so the
  /// association's unit check (a file's ranges or bearings in a wrong unit) is not run on them. A
  /// simulation's slow wander (a Gauss-Markov error with a correlation time near the recording's
  /// span) can take a realization's median range 25 % off at close range, which that check would
  /// refuse as a wrong unit. Not written by write_folder: a folder read back is checked as any.
  bool simulated = false;

  /// The sensor names of `detections`, sorted and distinct.
  std::vector<std::string> sensors() const;
  /// truth with every unknown height (a truth.csv without h_m: surface targets, e.g. AIS) set to
  /// the observer's first height, the level of the diagnosis's local frame. The multi-sensor
  /// diagnosis is 2-D (north, east); the height enters only through the frame's curvature: 40 m
  /// of height moves a target 10 km away by 6 cm horizontally.
  std::map<std::string, std::vector<GeoSample>> truth_on_level() const;
  /// Read and validate a folder (see the file comment); ConfigError naming file:line:column for
  /// a cell the format forbids, then validate(dir).
  static MultiSensorData read_folder(const std::string& dir);
  /// The shared plausibility layer (common/io/plausible.hpp) over the data, whatever its source:
  /// times finite and within +-1e10 s; observer positions in range with a plausible height and
  /// within 2000 km of the first one; truth positions in range (height where known) and within
  /// 2000 km of the observer's first position; ranges in (0, 1e6] m, angles finite. ConfigError
  /// naming `source`, the table and the sample index.
  void validate(const std::string& source) const;
  /// Write the folder (created if needed): t %.6f s, lat/lon %.10f deg, h %.4f m, range %.3f m,
  /// angles %.6f deg; optional columns only when some value is known; truth.csv only with truth
  /// and targets.csv (hull %.2f m) only with hull sizes (a stale one is removed); each CSV with its NAME.units.json (csv_columns.hpp). Throws naming
  /// the file when a write fails (e.g. disk full) and ConfigError for names the format cannot hold.
  void write_folder(const std::string& dir) const;
  /// The files' columns (unit and meaning of each), with or without their optional column.
  static std::vector<CsvColumnDoc> observer_columns(bool heading);
  static std::vector<CsvColumnDoc> detections_columns(bool elevation);
  static std::vector<CsvColumnDoc> truth_columns(bool height);
  static std::vector<CsvColumnDoc> targets_columns();
};

/// True if `s` is a valid sensor name ([a-z0-9_]+).
bool valid_sensor_name(const std::string& s);
/// True if `s` is a valid target name ([A-Za-z0-9_]+).
bool valid_target_name(const std::string& s);

}  // namespace rnav
