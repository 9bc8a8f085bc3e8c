// The multi-sensor interchange folder (observer.csv, detections.csv, truth.csv).
#include "test/fuzz/fuzz_folder.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  rnav::MultiSensorData::read_folder(write_folder("multi", {"observer.csv", "detections.csv", "truth.csv"}, data, size));
}
