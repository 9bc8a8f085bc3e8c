// Lock-step simulation streams read back from an LCM event log (lcm-logger, `scripts/run
// --lcm-log`, or LcmLogTap): one realization, the attempt the clock accepted, every window of
// every stream exactly once and in order — or an error naming channel, realization, attempt,
// window, event number and file. Nothing is lost silently:
//   * the attempt used is the realization's highest one (the clock repeats a realization that
//     lost a message with attempt + 1); batches of earlier attempts are ignored;
//   * that attempt must have completed: SIM_WINDOW grants 0..L, the last with last_window, and
//     after them the clock moved on (a START of a later realization, or FINISH);
//   * per stream, batches of that attempt have windows 0..L exactly once, in log order, with
//     consecutive seq and the utime range of their grant;
//   * a message on a known channel that does not decode is an error (channel, event number);
//   * events on other channels are counted (summary()), not read.
#pragma once

#include "common/node/batch_decode.hpp"
#include "common/io/config.hpp"

#include <rnav/batch_header_t.hpp>
#include <rnav/sim_scenario_t.hpp>
#include <rnav/sim_window_t.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace rnav {

/// True if `file` is a regular file that starts with the LCM event-log sync word 0xEDA1DA01.
bool is_lcm_log(const std::string& file);

class LcmLogStreams {
 public:
  /// Declare a stream: `channel` carries batch type B (a struct with a batch_header_t `header`).
  template <class B> void add_stream(const std::string& channel);

  /// Read `file`, keep `realization` and check it as described above. Throws ConfigError.
  /// If `kind` is not empty and the log's SIM_SCENARIO names another scenario kind, that is
  /// the error (before any stream check).
  void read(const std::string& file, int realization, const std::string& kind = "");

  /// The stream's batches of the attempt used, in window order (valid while *this lives).
  template <class B> std::vector<const B*> batches(const std::string& channel) const;

  int realization() const { return realization_; }
  int attempt() const { return attempt_; }
  int n_windows() const { return static_cast<int>(grants_.size()); }
  /// utime_begin of window 0 (sim time 0 of the run, runner.epoch_utime).
  std::int64_t start_utime() const { return grants_.at(0).w.utime_begin; }
  /// The SIM_SCENARIO message of the attempt used (or, failing that, of an earlier attempt of
  /// the realization); nullptr if the log has none.
  const sim_scenario_t* scenario() const;
  const std::string& file() const { return file_; }
  /// One line: events, realization/attempt used, batches per stream, ignored channels.
  std::string summary() const;

 private:
  struct Item {
    std::int64_t event = 0;
    batch_header_t h;
    std::shared_ptr<const void> msg;
    std::uint64_t digest = 0;  // of the encoded bytes: a resend (RESEND recovery) is identical
  };
  struct Stream {
    std::string channel;
    std::function<bool(const void*, int, batch_header_t&, std::shared_ptr<const void>&)> decode;
    std::vector<Item> items;  // the realization's batches, all attempts, log order
    std::vector<const Item*> used;  // the attempt used, window order (after read)
  };
  struct Grant {
    std::int64_t event = 0;
    std::size_t index = 0;  // position in the file
    sim_window_t w;
  };

  std::string where(const std::string& channel) const;
  void check_grants(std::size_t moved_on_index, const std::string& abort_reason);
  void check_stream(Stream& s);
  Stream* find(const std::string& channel);
  const Stream& stream(const std::string& channel) const;

  std::vector<std::unique_ptr<Stream>> streams_;
  std::string file_;
  int realization_ = 0, attempt_ = 0;
  std::vector<Grant> grants_;  // of the attempt used, log order
  std::map<int, sim_scenario_t> scenarios_;  // attempt -> SIM_SCENARIO of the realization
  std::map<std::string, long> ignored_;      // channel -> events not read
  long n_events_ = 0, n_earlier_ = 0, n_other_realizations_ = 0, n_resent_ = 0;
};

// ---- template implementation ----

template <class B> void LcmLogStreams::add_stream(const std::string& channel) {
  auto s = std::make_unique<Stream>();
  s->channel = channel;
  s->decode = [](const void* data, int size, batch_header_t& h, std::shared_ptr<const void>& out) {
    auto b = std::make_shared<B>();
    if (!decode_batch(data, size, *b)) return false;
    h = b->header;
    out = std::move(b);
    return true;
  };
  streams_.push_back(std::move(s));
}

template <class B> std::vector<const B*> LcmLogStreams::batches(const std::string& channel) const {
  std::vector<const B*> out;
  for (const Item* it : stream(channel).used) out.push_back(static_cast<const B*>(it->msg.get()));
  return out;
}

}  // namespace rnav
