// The lock-step protocol shared by every simulation node (see README, "Lock-step protocol").
//
// The clock grants windows [utime_begin, utime_end) of (realization, attempt). A node processes
// window w once it holds the grant and one batch for w on each of its inputs, then publishes
// one batch per output channel (possibly empty) and an OK ack. Every input is checked:
//   - a batch seen before (same channel and window of the current attempt) must be
//     byte-identical: it is a resend and is ignored; a different one is an error;
//   - otherwise each channel's header.seq must run 0, 1, 2, ... (a gap or a step back is loss or
//     reordering: LOSS, and the clock repeats the realization);
//   - each (realization, attempt) must bring windows 0, 1, 2, ... exactly once.
// Loss is recovered, not repeated: the clock sends RESEND for an overdue window; a node that
// processed it acks again; one that never saw its START takes the RESEND as the START; one that
// misses inputs answers WAITING naming them, and their publishers publish the kept batches of
// that window again. The node keeps its outputs of the last window it processed for this.
// Watchdog: a node that hears nothing from the clock (grants, resends, heartbeats) for the peer
// timeout stops with exit code kClockSilentExit, naming the clock.
//
// Wire forms (runner.wire): "batch" sends each window's batch as one message (the checks above);
// "sample" sends one message per sample, of the sample type (BatchItems), and nothing for a
// window without samples. The publisher's OK ack then lists, per channel, the samples' count and
// each sample message's digest in publish order; a consumer assembles the window's batch from
// the samples it holds with exactly those digests, in that order (copies ignored), and asks for
// what is missing with WAITING as for a batch. Samples carry no window: they are matched to the
// ack by digest, and what a consumer holds is dropped once a window is assembled from it.
//
// Feedback inputs (add_feedback_input): a channel published by a node downstream of this one
// (the UAV's guidance uses the estimator's output). Window w takes that channel's batch of window
// w - 1 (window 0: an empty batch), which its publisher sent before acking w - 1, hence before
// the clock granted w: the loop is causal and deterministic. A consumer's
// WAITING for a feedback input names the window it needs (w - 1), so its publisher, for which that
// is the last window it processed, publishes the kept batch again.
#pragma once

#include "common/node/batch_decode.hpp"
#include "common/node/batch_items.hpp"
#include "common/node/bus.hpp"
#include "common/node/channels.hpp"

#include <rnav/batch_header_t.hpp>
#include <rnav/node_ack_t.hpp>
#include <rnav/sim_window_t.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace rnav {

/// (realization, attempt, window) of a batch or grant.
using WindowKey = std::tuple<int, int, int>;

/// A deliberate drop of one published batch (fault injection for tests): CHANNEL:R:W[:A[:K]].
struct DropSpec {
  std::string channel;
  int realization = 0, window = 0;
  int attempt = -1;       ///< -1 = every attempt
  int transmissions = -1; ///< drop the first K transmissions (the original, then resends); -1 = every one
  /// From "CHANNEL:R:W[:A[:K]]"; a ConfigError naming the text otherwise.
  static DropSpec parse(const std::string& text);
};

/// How the data channels travel (runner.wire).
enum class Wire { kBatch, kSample };
/// From "batch" or "sample"; std::invalid_argument otherwise (the scenario reader checks first).
Wire parse_wire(const std::string& text);

/// Exit code of a node whose clock fell silent (the runner names the clock).
inline constexpr int kClockSilentExit = 5;
/// [s wall] How long a node stays after FINISH to answer a repeated FINISH (its FINISHED
/// report may be lost; the clock repeats FINISH every 50 ms).
inline constexpr double kFinishLingerS = 0.5;
/// [s wall] How long a node waits for the first word of the clock: the runner starts the clock
/// last, after the optional lcm-logger has recorded a node's HELLO (at most 10 s).
inline constexpr double kClockStartupTimeoutS = 60;

class LockstepNode {
 public:
  /// @param peer_timeout_s [s wall] > 0: silence of the clock after which the node stops
  ///        (runner.peer_timeout_s)
  LockstepNode(Bus& bus, std::string name, double peer_timeout_s);
  virtual ~LockstepNode() = default;
  LockstepNode(const LockstepNode&) = delete;
  LockstepNode& operator=(const LockstepNode&) = delete;

  /// Call regularly with a monotonic wall time [s]: sends HELLO until the first grant and
  /// watches the clock (silent for the peer timeout: done, exit code kClockSilentExit).
  void poll(double wall_now_s);
  bool done() const { return done_; }
  /// 0 after FINISH, 3 after ABORT, kClockSilentExit when the clock fell silent.
  int exit_code() const { return exit_code_; }
  /// Why the node stopped, if not by FINISH (empty otherwise).
  const std::string& failure() const { return failure_; }
  /// Resent batches received and ignored (identical to the first copy), and batches published
  /// again on a consumer's WAITING.
  int duplicates_ignored() const { return duplicates_ignored_; }
  /// Messages of another run (another run id: Bus::run_id) heard and ignored: grants, acks and
  /// batches (reported to the clock with FINISHED).
  int foreign_ignored() const { return foreign_; }
  int republished() const { return republished_; }
  const std::string& name() const { return name_; }
  void add_drop(const DropSpec& d) { drops_.push_back(d); }
  /// Off: the node never stops for a silent clock (one process, where the clock cannot fall
  /// silent and wall time is simulated).
  void set_clock_watchdog(bool on) { clock_watchdog_ = on; }
  /// The wire form of every data channel (runner.wire); set before the first window.
  void set_wire(Wire w) { wire_ = w; }

 protected:
  /// A new (realization, attempt) starts: reset all per-realization state and re-seed.
  virtual void reset(const sim_window_t& w) = 0;
  /// All inputs of window w are here: publish this window's outputs; return samples published.
  virtual int process(const sim_window_t& w) = 0;
  /// The ensemble is complete (FINISH). Write final outputs here; throw on failure.
  virtual void finish(const sim_window_t& /*finish*/) {}
  /// The clock has moved past the realization last processed (next realization or FINISH):
  /// its data is final. Called before reset() of the next realization and before finish().
  virtual void commit() {}

  /// Register an input channel carrying batch type B (with a `header` field).
  template <class B> void add_input(const std::string& channel);
  /// Register a feedback input: window w gets the channel's batch of window w - 1 (see above).
  template <class B> void add_feedback_input(const std::string& channel);
  /// The batch of type B for the window being processed (a feedback input: of the window before).
  template <class B> const B& input(const std::string& channel) const;
  /// Fill `batch.header` for the window being processed and publish it (unless dropped).
  template <class B> void publish_batch(const std::string& channel, B& batch);

  const sim_window_t& current() const { return grant_; }
  Bus& bus() { return bus_; }

 private:
  struct InputStream {
    std::string channel;
    // wire = sample: the samples received and not yet used, by message digest (copies collapse),
    // the publisher's digests per window from its OK ack, and how to build the batch from them.
    std::map<std::uint64_t, std::shared_ptr<const void>> inbox;
    std::map<WindowKey, std::vector<std::uint64_t>> expected;
    std::function<std::shared_ptr<const void>(const std::vector<std::shared_ptr<const void>>&, const WindowKey&)> assemble;
    std::int64_t next_seq = 0;
    bool resync = false;  // a repeated attempt: messages lost in the failed one are already reported
    std::map<WindowKey, std::shared_ptr<const void>> store;
    std::map<WindowKey, std::uint64_t> digest;  // every batch of the current attempt: resends must match
    int delay = 0;                               // windows: 1 for a feedback input
    std::shared_ptr<const void> empty;           // a feedback input's batch before window 0
  };
  // The window whose batch `in` supplies to the granted window (none before window 0 of a feedback input).
  std::optional<WindowKey> needed_key(const InputStream& in) const;
  bool holds_needed(const InputStream& in) const;
  struct Output {  // what a channel got in the last processed window, kept for resends
    std::string channel;
    std::vector<std::vector<std::uint8_t>> messages;  // one batch, or one message per sample
    int n_samples = 0;
  };

  void on_grant(const sim_window_t& w);
  void on_resend(const sim_window_t& w);
  void on_peer_ack(const node_ack_t& a);
  void on_batch(InputStream& in, const batch_header_t& h, std::shared_ptr<const void> batch,
                std::uint64_t digest);
  void begin_attempt(const sim_window_t& w);
  void accept_grant(const sim_window_t& w);
  void try_process();
  void report(std::int8_t status, const std::string& detail, const std::vector<std::string>& missing = {},
              std::optional<int> window = std::nullopt);  // window: of the ack (default: the grant's)
  void fail(const std::string& detail);
  void stop(int code, const std::string& why);
  bool newer(int r, int a) const;
  void transmit(const Output& out);
  void on_sample(InputStream& in, std::uint64_t digest, std::shared_ptr<const void> sample);
  void try_assemble(InputStream& in);
  std::vector<std::string> missing_inputs() const;
  void report_waiting(const std::vector<std::string>& missing);

  Bus& bus_;
  std::string name_;
  double peer_timeout_s_;
  std::vector<std::unique_ptr<InputStream>> inputs_;
  std::map<std::string, std::int64_t> out_seq_;
  std::vector<DropSpec> drops_;
  std::map<std::pair<std::string, WindowKey>, int> transmissions_;  // per channel and window, for drops
  std::vector<Output> last_out_;
  WindowKey last_out_key_{-1, -1, -1};

  sim_window_t grant_{};
  bool started_ = false;       // any START seen
  bool have_grant_ = false;    // grant_ not yet processed
  bool failed_ = false;        // current attempt failed (LOSS reported)
  std::string failed_detail_;  // ... and the report, repeated on RESEND (the LOSS ack may be lost)
  bool processed_any_ = false; // something to commit
  int cur_r_ = -1, cur_a_ = -1, next_window_ = 0;
  double last_hello_s_ = -1e9, now_s_ = 0, first_poll_s_ = -1, last_clock_s_ = -1;
  bool clock_heard_ = false;  // a SIM_WINDOW message since the last poll()
  bool clock_watchdog_ = true;
  Wire wire_ = Wire::kBatch;
  bool finished_ = false;     // FINISH handled: lingering to answer a repeated FINISH
  double finished_at_s_ = -1;
  bool done_ = false;
  int exit_code_ = 0;
  std::string failure_;
  int published_ = 0, duplicates_ignored_ = 0, republished_ = 0, foreign_ = 0;
};

/// A 64-bit digest of a message's bytes (FNV-1a over words; tells a resend from a different batch).
std::uint64_t message_digest(const void* data, int size);

// ---- template implementation ----

template <class B> void LockstepNode::add_input(const std::string& channel) {
  using Sample = typename BatchItems<B>::Sample;
  inputs_.push_back(std::make_unique<InputStream>());
  InputStream* in = inputs_.back().get();
  in->channel = channel;
  in->assemble = [](const std::vector<std::shared_ptr<const void>>& samples, const WindowKey& key) {
    auto b = std::make_shared<B>();
    b->header.seq = std::get<2>(key);  // assembled from samples: no publish counter, no window times
    b->header.realization = std::get<0>(key);
    b->header.attempt = std::get<1>(key);
    b->header.window = std::get<2>(key);
    b->header.utime_begin = b->header.utime_end = 0;
    for (const auto& s : samples) BatchItems<B>::items(*b).push_back(*static_cast<const Sample*>(s.get()));
    b->n = static_cast<std::int32_t>(samples.size());
    return std::shared_ptr<const void>(std::move(b));
  };
  bus_.subscribe_raw(channel, [this, in](const std::string& ch, const void* data, int size) {
    if (wire_ == Wire::kSample) {
      auto s = std::make_shared<Sample>();
      if (s->decode(data, 0, size) != size)
        throw std::runtime_error(name_ + ": cannot decode a message on channel " + ch + " as one " +
                                 Sample::getTypeName() + " (runner.wire = sample: every process of the run must use it)");
      on_sample(*in, message_digest(data, size), std::move(s));
      return;
    }
    auto b = std::make_shared<B>();
    if (!decode_batch(data, size, *b))
      throw std::runtime_error(name_ + ": cannot decode a message on channel " + ch + " as a " + B::getTypeName() +
                               " (wrong type or corrupt; runner.wire = batch: every process of the run must use it)");
    if (b->header.run_id != bus_.run_id()) {  // another run's batch on this network
      ++foreign_;
      return;
    }
    on_batch(*in, b->header, b, message_digest(data, size));
  });
}

template <class B> void LockstepNode::add_feedback_input(const std::string& channel) {
  add_input<B>(channel);
  auto empty = std::make_shared<B>();
  empty->n = 0;
  inputs_.back()->delay = 1;
  inputs_.back()->empty = std::move(empty);
}

template <class B> const B& LockstepNode::input(const std::string& channel) const {
  for (const auto& in : inputs_)
    if (in->channel == channel) {
      const auto key = needed_key(*in);
      if (!key) return *static_cast<const B*>(in->empty.get());
      auto it = in->store.find(*key);
      if (it != in->store.end()) return *static_cast<const B*>(it->second.get());
    }
  throw std::logic_error(name_ + ": no batch on " + channel + " for the current window");
}

template <class B> void LockstepNode::publish_batch(const std::string& channel, B& batch) {
  auto& seq = out_seq_[channel];
  batch.header.seq = seq++;
  batch.header.realization = grant_.realization;
  batch.header.attempt = grant_.attempt;
  batch.header.window = grant_.window;
  batch.header.utime_begin = grant_.utime_begin;
  batch.header.utime_end = grant_.utime_end;
  batch.header.run_id = bus_.run_id();
  published_ += batch.n;
  Output out{channel, {}, batch.n};
  auto encode = [&](const auto& m) {
    const int n = m.getEncodedSize();
    out.messages.emplace_back(static_cast<std::size_t>(n));
    if (m.encode(out.messages.back().data(), 0, n) != n)
      throw std::runtime_error(name_ + ": cannot encode a message for " + channel);
  };
  if (wire_ == Wire::kSample)
    for (const auto& s : BatchItems<B>::items(batch)) encode(s);
  else
    encode(batch);
  transmit(out);
  last_out_.push_back(std::move(out));
}

}  // namespace rnav
