// The skeleton of a free-running node with two inputs, A and B, each carrying its lock-step
// batch type or its sample type (FreeInput, see free_input.hpp; all inputs in the same form).
// Batches: a batch that is the next of its flight enters its flight (a newer (realization,
// attempt) ends the current one, counted incomplete if anything of it still waits) and is queued;
// every window both queues hold is handed to the node as a pair (on_window), in window order.
// Samples: each is handed to the node as it comes (on_sample_a / on_sample_b); at the end of the
// input the node decides what still waits (on_end_of_samples). The node supplies only these hooks,
// the reset for a new flight (on_new_flight) and its own part of the summary line.
#pragma once

#include "common/node/bus.hpp"
#include "common/node/free_input.hpp"
#include "common/node/free_node.hpp"

#include <deque>
#include <stdexcept>
#include <string>
#include <utility>

namespace rnav {

template <class BatchA, class SampleA, class BatchB, class SampleB> class PairedFreeNode : public FreeNode {
 public:
  void flush() final {
    // Single samples: the feed has ended, the node decides what waits with what arrived.
    // Batches: the lock-step run decided everything by its last window; what waits belongs to
    // an incomplete flight (reported).
    if (form_.form() == InputForm::Form::kSamples) on_end_of_samples();
    else if (holds_flight()) ++incomplete_flights_;
  }
  std::string summary() const final {
    return free_input_summary(received_, form_, flights_, incomplete_flights_, skips_) + "; " + output_summary();
  }

 protected:
  /// `name`: the program's short name ("prl_bias"), for the error of windows out of step;
  /// `channel_a`, `channel_b`: the input channels. Nothing is subscribed before listen().
  PairedFreeNode(Bus& bus, std::string name, const std::string& channel_a, const std::string& channel_b)
      : bus_(bus), name_(std::move(name)), in_a_(channel_a, form_, skips_), in_b_(channel_b, form_, skips_) {}

  /// Subscribe both inputs. The node's constructor calls it last, once its own checks passed
  /// (a Bus cannot unsubscribe a node that failed to construct).
  void listen() {
    bus_.subscribe_raw(in_a_.channel(), [this](const std::string&, const void* d, int n) {
      ++received_;
      in_a_.take(d, n, flight_, queue(q_a_), [this](const SampleA& s) { on_sample_a(s); });
    });
    bus_.subscribe_raw(in_b_.channel(), [this](const std::string&, const void* d, int n) {
      ++received_;
      in_b_.take(d, n, flight_, queue(q_b_), [this](const SampleB& s) { on_sample_b(s); });
    });
  }

  /// Batches: both inputs' batches of one window, in window order from 0 of each flight.
  virtual void on_window(const BatchA& a, const BatchB& b) = 0;
  /// Single samples: one of input A, as it comes (a copy of one seen lately already skipped).
  virtual void on_sample_a(const SampleA& s) = 0;
  /// Single samples: one of input B, as it comes.
  virtual void on_sample_b(const SampleB& s) = 0;
  /// Single samples: the input has ended; decide and publish everything still waiting.
  virtual void on_end_of_samples() = 0;
  /// Batches: flight `f` begins (the first, or a newer one ending the current): reset for it.
  virtual void on_new_flight(const FlightKey& f) = 0;
  /// Batches: whether the node itself holds inputs of the current flight not yet decided.
  virtual bool holds_undecided() const { return false; }
  /// The summary line's end: what the node published ("N plot(s) estimated and published").
  virtual std::string output_summary() const = 0;

  /// The bus the node listens and publishes on.
  Bus& bus() { return bus_; }

 private:
  /// What a batch that is the next of its flight does: it enters its flight (enter_flight), is
  /// queued on `q`, and every window both inputs hold is processed (drain_windows).
  template <class B> auto queue(std::deque<B>& q) {
    return [this, &q](B&& b) {
      enter_flight({b.header.realization, b.header.attempt});
      q.push_back(std::move(b));
      drain_windows();
    };
  }
  /// A batch of flight `f` arrived: a newer flight ends the current one.
  void enter_flight(const FlightKey& f) {
    if (f <= flight_) return;
    if (holds_flight()) ++incomplete_flights_;
    q_a_.clear();
    q_b_.clear();
    on_new_flight(f);
    flight_ = f;
    ++flights_;
  }
  /// Hand over every window both inputs hold.
  void drain_windows() {
    while (!q_a_.empty() && !q_b_.empty()) {
      if (q_a_.front().header.window != q_b_.front().header.window)  // BatchOrder keeps both in window order from 0
        throw std::logic_error(name_ + " --free: " + in_a_.channel() + " and " + in_b_.channel() +
                               " windows out of step");
      on_window(q_a_.front(), q_b_.front());
      q_a_.pop_front();
      q_b_.pop_front();
    }
  }
  /// Whether anything of the current flight waits (queued batches, or inputs the node holds).
  bool holds_flight() const { return !q_a_.empty() || !q_b_.empty() || holds_undecided(); }

  Bus& bus_;
  std::string name_;
  InputForm form_;   // the form of every input (the first message sets it)
  FreeSkips skips_;  // resends and stale batches skipped, over both inputs
  FreeInput<BatchA, SampleA> in_a_;
  FreeInput<BatchB, SampleB> in_b_;
  FlightKey flight_{-1, -1};
  std::deque<BatchA> q_a_;  // batches of the current flight not yet processed
  std::deque<BatchB> q_b_;
  long flights_ = 0, incomplete_flights_ = 0;
};

}  // namespace rnav
