// Consuming a project stream without the lock-step clock (a free-running estimator). A channel
// carries either its lock-step batch type (a recorded lock-step run replayed by lcm-logplayer)
// or one sample per message (a real-time run, or a real sensor publishing the sample type);
// the message's type fingerprint tells which. Batches are checked as the lock-step node checks
// them: per channel and (realization, attempt), windows and seq in order; a copy of a window
// already seen is a resend and is skipped; a gap or a step back is an error naming the channel.
#pragma once

#include "batch_decode.hpp"

#include <rnav/batch_header_t.hpp>

#include <cstdint>
#include <stdexcept>
#include <deque>
#include <string>
#include <unordered_set>
#include <tuple>

namespace rnav {

/// The type fingerprint an LCM message starts with (8 bytes, big-endian); 0 if size < 8.
std::int64_t message_fingerprint(const void* data, int size);

/// (realization, attempt) of a batch: one simulated flight.
using FlightKey = std::pair<int, int>;

/// Order of one channel's batches (see the file comment).
class BatchOrder {
 public:
  explicit BatchOrder(std::string channel) : channel_(std::move(channel)) {}
  enum class Step {
    kNext,     ///< the next window of the current flight (or the first of a new one)
    kResend,   ///< a window already seen: skip it
    kStale,    ///< a batch of an older flight than the current one: skip it
  };
  /// Check a batch header; throws std::runtime_error naming the channel on a gap or a step back.
  Step see(const batch_header_t& h);

 private:
  std::string channel_;
  bool any_ = false;
  FlightKey flight_{-1, -1};
  int next_window_ = 0;
  std::int64_t next_seq_ = 0;
};

/// Decode one sample of type T, or throw naming the channel.
template <class T> T decode_sample(const void* data, int size, const std::string& channel) {
  T m;
  if (m.decode(data, 0, size) != size) throw std::runtime_error("cannot decode a message on " + channel + " (corrupt)");
  return m;
}
/// Decode a batch of type B (sizes checked first, see batch_decode.hpp), or throw naming the channel.
template <class B> B decode_whole_batch(const void* data, int size, const std::string& channel) {
  B b;
  if (!decode_batch(data, size, b)) throw std::runtime_error("cannot decode a batch on " + channel + " (corrupt)");
  return b;
}

/// The form a free-running node's inputs come in: the first message sets it for all inputs.
class InputForm {
 public:
  enum class Form { kUnknown, kBatches, kSamples };
  /// Record `f` for `channel`; throws naming it if the inputs came in the other form before.
  void expect(Form f, const std::string& channel);
  Form form() const { return form_; }

 private:
  Form form_ = Form::kUnknown;
};

/// The sample messages of one channel seen lately, by digest: a byte-identical copy (a lock-step
/// publisher's resend in a runner.wire=sample recording, e.g. a real-time run's) is recognised
/// and skipped rather than taken for a step back in time.
class RecentCopies {
 public:
  /// [messages] How many of the latest messages are remembered: far more than any resend lags.
  static constexpr std::size_t kCapacity = 4096;
  /// True if these bytes were seen among the last kCapacity messages; remembers them otherwise.
  bool seen(const void* data, int size);

 private:
  std::deque<std::uint64_t> order_;
  std::unordered_set<std::uint64_t> set_;
};

/// The error for a message whose fingerprint is neither the batch nor the sample type.
std::string foreign_type_error(const std::string& channel, const char* batch_type, const char* sample_type);

}  // namespace rnav
