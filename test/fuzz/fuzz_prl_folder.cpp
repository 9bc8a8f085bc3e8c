// The landing-radar flight-test folder (site.json, radar.csv, nav.csv, truth.csv).
#include "test/fuzz/fuzz_folder.hpp"
#include "estimators/diagnosis/prl_flight_data.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  rnav::PrlFlightData::read_folder(write_folder("prl", {"site.json", "radar.csv", "nav.csv", "truth.csv"}, data, size));
}
