// The ADS-B record parser (JSON array of records).
#include "sim/trajectory/adsb_records.hpp"
#include "test/fuzz/fuzz_target.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  rnav::parse_adsb_records(std::string(reinterpret_cast<const char*>(data), size), "fuzz input");
}
