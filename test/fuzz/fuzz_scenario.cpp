// The scenario parser: landing-radar and UAV scenario files (kind from the file).
#include "common/io/config.hpp"
#include "test/fuzz/fuzz_target.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  const std::string f = write_scratch("scenario.json", data, size);
  if (rnav::scenario_kind(f) == "uav") rnav::UavScenario::load(f);
  else rnav::Scenario::load(f);
}
