// The azimuth-only folder (observer.csv, bearings.csv, truth.csv).
#include "estimators/diagnosis/azimuth_data.hpp"
#include "test/fuzz/fuzz_folder.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  rnav::AzimuthData::read_folder(write_folder("azimuth", {"observer.csv", "bearings.csv", "truth.csv"}, data, size));
}
