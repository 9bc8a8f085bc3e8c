// The lock-step protocol shared by every simulation node (see README, "Lock-step protocol").
//
// The clock grants windows [utime_begin, utime_end) of (realization, attempt). A node processes
// window w once it holds the grant and one batch for w on each of its inputs, then publishes
// one batch per output channel (possibly empty) and an OK ack. Every input is checked:
//   - each channel's header.seq must run 0, 1, 2, ... (a gap is loss, a repeat or step back
//     is duplication or reordering);
//   - each (realization, attempt) must bring windows 0, 1, 2, ... exactly once;
//   - a grant whose inputs do not all arrive within stall_timeout_s (wall) is loss.
// Any of these makes the node publish a LOSS ack naming channel, realization, window and seq;
// the clock then repeats the realization. Batches of older attempts are ignored.
#pragma once

#include "bus.hpp"
#include "channels.hpp"

#include <rnav/batch_header_t.hpp>
#include <rnav/node_ack_t.hpp>
#include <rnav/sim_window_t.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace rnav {

/// (realization, attempt, window) of a batch or grant.
using WindowKey = std::tuple<int, int, int>;

/// A deliberate drop of one published batch (fault injection for tests): CHANNEL:R:W[:A].
struct DropSpec {
  std::string channel;
  int realization = 0, window = 0;
  int attempt = -1;  ///< -1 = every attempt
  static DropSpec parse(const std::string& text);
};

class LockstepNode {
 public:
  LockstepNode(Bus& bus, std::string name, double stall_timeout_s);
  virtual ~LockstepNode() = default;
  LockstepNode(const LockstepNode&) = delete;
  LockstepNode& operator=(const LockstepNode&) = delete;

  /// Call regularly with a monotonic wall time [s]: sends HELLO until the first grant and
  /// reports loss for a grant whose inputs are overdue.
  void poll(double wall_now_s);
  bool done() const { return done_; }
  /// 0 after FINISH, non-zero after ABORT.
  int exit_code() const { return exit_code_; }
  const std::string& name() const { return name_; }
  void add_drop(const DropSpec& d) { drops_.push_back(d); }

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
  /// The batch of type B for the window being processed.
  template <class B> const B& input(const std::string& channel) const;
  /// Fill `batch.header` for the window being processed and publish it (unless dropped).
  template <class B> void publish_batch(const std::string& channel, B& batch);

  const sim_window_t& current() const { return grant_; }
  Bus& bus() { return bus_; }

 private:
  struct InputStream {
    std::string channel;
    std::int64_t next_seq = 0;
    bool resync = false;  // a repeated attempt: messages lost in the failed one are already reported
    std::map<WindowKey, std::shared_ptr<const void>> store;
  };

  void on_grant(const sim_window_t& w);
  void on_batch(InputStream& in, const batch_header_t& h, std::shared_ptr<const void> batch);
  void try_process();
  void report(std::int8_t status, const std::string& detail);
  void fail(const std::string& detail);
  bool newer(int r, int a) const;
  bool dropped(const std::string& channel) const;

  Bus& bus_;
  std::string name_;
  double stall_timeout_s_;
  std::vector<std::unique_ptr<InputStream>> inputs_;
  std::map<std::string, std::int64_t> out_seq_;
  std::vector<DropSpec> drops_;

  sim_window_t grant_{};
  bool started_ = false;       // any START seen
  bool have_grant_ = false;    // grant_ not yet processed
  bool failed_ = false;        // current attempt failed (LOSS reported)
  bool processed_any_ = false; // something to commit
  int cur_r_ = -1, cur_a_ = -1, next_window_ = 0;
  double grant_wall_s_ = -1, last_hello_s_ = -1e9, now_s_ = 0;
  bool done_ = false;
  int exit_code_ = 0;
  int published_ = 0;
};

// ---- template implementation ----

template <class B> void LockstepNode::add_input(const std::string& channel) {
  inputs_.push_back(std::make_unique<InputStream>());
  InputStream* in = inputs_.back().get();
  in->channel = channel;
  bus_.subscribe<B>(channel, [this, in](const B& b) {
    on_batch(*in, b.header, std::make_shared<const B>(b));
  });
}

template <class B> const B& LockstepNode::input(const std::string& channel) const {
  for (const auto& in : inputs_)
    if (in->channel == channel) {
      auto it = in->store.find({grant_.realization, grant_.attempt, grant_.window});
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
  published_ += batch.n;
  if (!dropped(channel)) bus_.publish(channel, batch);
}

}  // namespace rnav
