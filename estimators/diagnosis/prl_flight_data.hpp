// A landing-radar flight test in the CSV interchange format (README, "Measured data"):
//   site.json   {"radar": {"lat_deg", "lon_deg", "h_m", "azimuth_reference_deg"},
//                "runway": {"threshold_lat_deg", "threshold_lon_deg", "threshold_h_m", "heading_deg"}}
//   radar.csv   t_s,range_m,azimuth_deg,elevation_deg   (slant range; azimuth in the radar's
//               horizontal plane from the true bearing azimuth_reference_deg, clockwise
//               positive; elevation above the radar's local horizontal)
//   nav.csv     t_s,lat_deg,lon_deg,h_m                (WGS84, ellipsoidal height; any rate)
//   truth.csv   optional, nav's columns
// Header lines required, extra columns ignored, rows in time order; anything else is an error
// naming file, line and column.
#pragma once

#include "common/io/csv_columns.hpp"
#include "common/physics/frames.hpp"

#include <string>
#include <vector>

namespace rnav {

struct PrlFlightData {
  Geodetic radar_site;
  double azimuth_reference_deg = 0;
  Geodetic threshold;
  double heading_deg = 0;
  std::vector<double> t_s;    ///< radar plot times [s]
  std::vector<Polar> plots;   ///< radar plots (course = azimuth, glide = elevation) [m, rad, rad]
  std::vector<GeoSample> nav;
  std::vector<GeoSample> truth;  ///< empty when there is no truth.csv

  static PrlFlightData read_folder(const std::string& dir);
  /// Every value within its physical range and every position near the radar site
  /// (common/io/plausible.hpp); throws ConfigError naming `source`, the sample and the value. The CSV
  /// and LCM-log readers both call it.
  void validate(const std::string& source) const;
  /// Write the folder (created if needed): site.json, radar.csv, nav.csv and truth.csv (with
  /// truth), each CSV with its NAME.units.json (csv_columns.hpp).
  void write_folder(const std::string& dir) const;
  /// radar.csv's columns; nav.csv's and truth.csv's are geo_track_columns (csv_columns.hpp).
  static std::vector<CsvColumnDoc> radar_columns();
  LocalLevelFrame radar_frame() const { return LocalLevelFrame(radar_site, azimuth_reference_deg); }
};

}  // namespace rnav
