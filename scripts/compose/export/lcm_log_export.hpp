// LCM event logs of in-process simulation runs: what `scripts/run --lcm-log` records from the
// multi-process run, without a network (tests, and data with a known hidden effect).
#pragma once

#include "common/node/bus.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lcm {
class LogFile;
}

namespace rnav {

/// Records every message published on an InprocBus into an LCM event log, in publish order
/// (InprocBus::on_publish). Event timestamps are a counter (1 us apart from
/// `first_timestamp_us`), not wall time: the reader relies on event order only.
class LcmLogTap {
 public:
  LcmLogTap(InprocBus& bus, const std::string& file, std::int64_t first_timestamp_us = 0);
  ~LcmLogTap();
  LcmLogTap(const LcmLogTap&) = delete;
  LcmLogTap& operator=(const LcmLogTap&) = delete;
  long events() const { return n_; }

 private:
  InprocBus& bus_;
  std::string file_;
  std::unique_ptr<lcm::LogFile> log_;
  std::int64_t t_;
  long n_ = 0;
};

/// Run realizations 0..n-1 of a scenario file (with overrides, as `scripts/run` would) in one
/// process and record every message into `log_file`, including the clock's SIM_SCENARIO.
/// prl: trajectory, snsins, prl, prl_bias; uav: target, uav, uav_tma (no logger).
/// `drops`: CHANNEL:R:W[:A] losses injected at every publisher (repeated attempts).
/// Returns 0 on success, else the in-process clock's exit code (and `failure`).
int export_lcm_log(const std::string& scenario_file, const std::vector<std::string>& overrides,
                   std::int64_t seed, int n, const std::string& log_file,
                   const std::vector<std::string>& drops = {}, std::string* failure = nullptr);

}  // namespace rnav
