// The Autoferry dataset (test/data/autoferry, its README) into the project's measured-data
// formats. One scenario is two JSON arrays of equal length: NAME_detections.json (one record per
// sensor scan: sensorID 1 lidar, 2 radar, 3 IR, 4 EO; time [Unix s]; ownshipPosition [N, E] in
// Piren NED [m]; measurement: bearings [rad] for 3/4, Cartesian offsets [m] for 1/2) and
// NAME_groundTruth.json (per record a list of {targetID, position [N, E, D] Piren NED [m], time}).
// Frames: Piren NED (origin 63.4389029083 N, 10.39908278 E, 39.923 m; x north, y east) to WGS84
// through the local level frame at that origin. Every JSON value is checked before use; a bad one
// is a ConfigError naming the file, the record and the key.
#pragma once

#include "estimators/diagnosis/azimuth_data.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace rnav {

/// The two documents of one scenario and the names that errors quote.
struct AutoferryRecords {
  nlohmann::json detections;    ///< array of scan records
  nlohmann::json ground_truth;  ///< array, same length, of lists of target states
  std::string detections_name;  ///< file name (or other source) of `detections`
  std::string ground_truth_name;
};

/// Read SCENARIO_DIR/NAME_detections.json and NAME_groundTruth.json, NAME = the folder's name.
AutoferryRecords load_autoferry(const std::string& scenario_dir);

/// Every sensor and target in the multi-sensor format (multi_sensor_data.hpp): the ferry's
/// positions (the first record of a time wins), every scan with its detections (an empty-scan row
/// for a scan without detection), both boats' truth de-duplicated. Times rounded to the
/// microsecond the CSV holds. Checked: record times strictly increase per sensor, a target's
/// repeated time carries the same position, and the result passes MultiSensorData::validate.
MultiSensorData autoferry_to_multi(const AutoferryRecords& r);

/// One camera's bearings in the azimuth-only format (azimuth_data.hpp): `sensor` "eo" or "ir",
/// `target` 1 or 2 (its truth); the ferry's positions at that camera's frames (a record not after
/// the previous one of that camera is skipped). The result passes AzimuthData::validate.
AzimuthData autoferry_to_azimuth(const AutoferryRecords& r, const std::string& sensor, int target);

}  // namespace rnav
