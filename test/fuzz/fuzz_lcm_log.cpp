// The LCM event-log readers of the diagnosis (landing radar and azimuth-only).
#include "test/fuzz/fuzz_target.hpp"
#include "estimators/diagnosis/io/lcm_log_input.hpp"

#include <exception>

void rnav::fuzz::run_one(const std::uint8_t* data, std::size_t size) {
  const std::string f = write_scratch("run.lcmlog", data, size);
  try {
    rnav::read_prl_lcm_log(f, rnav::LcmLogOptions{});
  } catch (const std::exception&) {
  }
  rnav::read_uav_lcm_log(f, rnav::LcmLogOptions{});
}
