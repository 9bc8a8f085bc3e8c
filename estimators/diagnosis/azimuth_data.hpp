// Azimuth-only observation data in the CSV interchange format (README, "Measured data"):
//   observer.csv  t_s,lat_deg,lon_deg,h_m     (the observer's navigation solution)
//   bearings.csv  t_s,bearing_deg             (true bearing from observer to object, clockwise
//                                              from north; several rows with one t_s = several
//                                              detections in one frame)
//   truth.csv     optional: t_s,lat_deg,lon_deg of the object
// Header required, extra columns ignored, rows in time order (bearings: non-decreasing).
#pragma once

#include "common/physics/frames.hpp"
#include "estimators/diagnosis/prl_flight_data.hpp"

#include <string>
#include <vector>

namespace rnav {

struct BearingFrame {
  double t_s = 0;
  std::vector<double> bearings_rad;  ///< all detections of the frame
};

struct AzimuthData {
  std::vector<GeoSample> observer;
  std::vector<BearingFrame> frames;
  std::vector<GeoSample> truth;  ///< h_m unused; empty without truth.csv

  static AzimuthData read_folder(const std::string& dir);
  /// Every value within its physical range and every position near the observer's first one
  /// (common/io/plausible.hpp); throws ConfigError naming `source`, the sample and the value. The CSV
  /// and LCM-log readers both call it.
  void validate(const std::string& source) const;
  /// Write the folder (created if needed): observer.csv, bearings.csv and truth.csv (with
  /// truth), each with its NAME.units.json (csv_columns.hpp).
  void write_folder(const std::string& dir) const;
  /// The files' columns (unit and meaning of each).
  static std::vector<CsvColumnDoc> observer_columns();
  static std::vector<CsvColumnDoc> bearings_columns();
  static std::vector<CsvColumnDoc> truth_columns();
};

}  // namespace rnav
