// Consuming a project stream without the lock-step clock (a free-running estimator). A channel
// carries either its lock-step batch type (a recorded lock-step run replayed by lcm-logplayer)
// or one sample per message (a real-time run, or a real sensor publishing the sample type);
// the message's type fingerprint tells which. Batches are checked as the lock-step node checks
// them: per channel and (realization, attempt), windows and seq in order; a copy of a window
// already seen is a resend and is skipped; a gap or a step back is an error naming the channel.
#pragma once

#include "common/node/batch_decode.hpp"

#include <rnav/batch_header_t.hpp>

#include <cstdint>
#include <stdexcept>
#include <deque>
#include <limits>
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

/// The time stamps of one input's single samples, which must run forward: a step back means the
/// samples of another flight, and a free-running node keeps one flight's state.
class ForwardTimes {
 public:
  enum class Ties {
    kAllowed,  ///< several samples may share a time stamp (e.g. bearings of one frame)
    kRefused,  ///< each sample is later than the previous one
  };
  ForwardTimes(std::string channel, Ties ties) : channel_(std::move(channel)), ties_(ties) {}
  /// [us] Take time `t`. On a step back (or a repeat, with kRefused) throws std::runtime_error
  /// "CHANNEL: WHAT (a new flight needs a new estimator)", WHAT = describe(last()).
  template <class Describe> void take(std::int64_t t, Describe&& describe) {
    if (t < last_ || (ties_ == Ties::kRefused && t == last_))
      throw std::runtime_error(channel_ + ": " + describe(last_) + " (a new flight needs a new estimator)");
    last_ = t;
  }
  /// [us] The latest time taken; std::numeric_limits<std::int64_t>::min() before the first.
  std::int64_t last() const { return last_; }
  /// Whether a time has been taken.
  bool any() const { return last_ != std::numeric_limits<std::int64_t>::min(); }

 private:
  std::string channel_;
  Ties ties_;
  std::int64_t last_ = std::numeric_limits<std::int64_t>::min();
};

/// The error for a message whose fingerprint is neither the batch nor the sample type.
std::string foreign_type_error(const std::string& channel, const char* batch_type, const char* sample_type);

/// What a free-running node's inputs skipped (one tally for all its channels).
struct FreeSkips {
  long resends = 0;  ///< batches of a window already seen, and byte-identical copies of samples
  long stale = 0;    ///< batches of an older flight than the current one
};

/// The node's summary line up to its own output count: "N message(s) received as batches: F
/// flight(s), I of them incomplete, R resent and S stale batch(es) skipped" (or "... as single
/// samples", or nothing after "received" before any input).
std::string free_input_summary(long received, const InputForm& form, long flights, long incomplete, const FreeSkips& skips);

/// One input channel of a free-running node, carrying batch type Batch (with a batch_header_t
/// `header`) or sample type Sample: the dispatch every such input shares (see the file comment).
/// take() hands a batch that is the next of its flight to on_batch (a resend, or a batch of a
/// flight older than the node's current one, is skipped and counted), and a sample that is not a
/// copy of one seen lately to on_sample; a message of any other type, or in the other form than
/// the node's inputs so far (`form`, shared by the node's inputs), throws naming the channel.
template <class Batch, class Sample> class FreeInput {
 public:
  FreeInput(std::string channel, InputForm& form, FreeSkips& skips)
      : channel_(std::move(channel)), form_(form), skips_(skips), order_(channel_) {}

  template <class OnBatch, class OnSample>
  void take(const void* data, int size, const FlightKey& current, OnBatch&& on_batch, OnSample&& on_sample) {
    const std::int64_t fp = message_fingerprint(data, size);
    if (fp == Batch::getHash()) {
      form_.expect(InputForm::Form::kBatches, channel_);
      Batch b = decode_whole_batch<Batch>(data, size, channel_);
      const BatchOrder::Step s = order_.see(b.header);
      if (s == BatchOrder::Step::kResend) {
        ++skips_.resends;
      } else if (s == BatchOrder::Step::kStale || FlightKey{b.header.realization, b.header.attempt} < current) {
        ++skips_.stale;
      } else {
        on_batch(std::move(b));
      }
    } else if (fp == Sample::getHash()) {
      form_.expect(InputForm::Form::kSamples, channel_);
      if (copies_.seen(data, size)) {
        ++skips_.resends;  // a publisher's resend
        return;
      }
      on_sample(decode_sample<Sample>(data, size, channel_));
    } else {
      throw std::runtime_error(foreign_type_error(channel_, Batch::getTypeName(), Sample::getTypeName()));
    }
  }
  const std::string& channel() const { return channel_; }

 private:
  std::string channel_;
  InputForm& form_;
  FreeSkips& skips_;
  BatchOrder order_;
  RecentCopies copies_;
};

}  // namespace rnav
