// The lock-step clock: grants windows to every node, waits for their acks, recovers a lost
// message by RESEND (the nodes re-ack, or name what they miss and its publisher sends it again),
// repeats a realization only when recovery fails within runner.ack_timeout_s (up to
// runner.max_attempts), fails the run naming a node that falls silent (runner.peer_timeout_s),
// and finishes or aborts the run. It sends a heartbeat when it has sent nothing for
// peer_timeout_s / 8, so that nodes can tell a silent clock.
// Transport-agnostic (Bus) and time-agnostic (poll(wall_now)): the same code drives the
// multi-process run over LCM and the single-process ensemble.
#pragma once

#include "common/node/bus.hpp"
#include "common/node/runner_options.hpp"
#include "common/physics/sim_time.hpp"

#include <rnav/node_ack_t.hpp>

#include <unordered_set>

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace rnav {

struct ConductorOptions {
  int n_realizations = 1;          ///< ensemble size (of this run: a shard's count), >= 1
  /// Index of the first realization run: realizations first_realization ...
  /// first_realization + n_realizations - 1 (a shard of a larger ensemble; each realization's
  /// random streams depend on its index only). >= 0.
  int first_realization = 0;
  std::int64_t seed = 1;           ///< ensemble seed
  std::vector<std::string> nodes;  ///< names of the nodes that must ack every window
  bool realtime = false;           ///< pace windows to the wall clock
  double speed = 1.0;              ///< realtime: sim seconds per wall second, > 0
  double hello_timeout_s = 30;     ///< [s wall] how long to wait for every node's HELLO
  /// If not empty: published on SIM_SCENARIO (sim_scenario_t) before window 0 of every
  /// (realization, attempt), so event logs of the run carry their scenario. No node reads it.
  std::string scenario_kind, scenario_source, scenario_json;
};

struct RetryEvent {
  int realization = 0, attempt = 0;
  std::string reason;
};

/// A RESEND the clock sent: the window and what was overdue (the nodes not yet acked, and what
/// those that answered WAITING miss).
struct ResendEvent {
  int realization = 0, attempt = 0, window = 0;
  std::string reason;
  double wall_s = 0;  ///< [s wall] when it was sent, from the clock's first poll
  double wait_s = 0;  ///< [s wall] how long the window had made no progress before it
};

class Conductor {
 public:
  /// @param runner      lock-step options (window, timeouts, attempts, epoch)
  /// @param step_s      [s] truth grid step; the realization end is rounded up to it
  /// @param duration_s  [s] sim time of the scenario's last truth sample
  Conductor(Bus& bus, const RunnerOptions& runner, double step_s, const ConductorOptions& o,
            double duration_s);

  /// Drive the protocol; call often with a monotonic wall time [s].
  void poll(double wall_now_s);
  bool done() const { return state_ == State::kDone; }
  /// 0 success, 3 a realization failed max_attempts times, 4 a node error / missing node.
  int exit_code() const { return exit_code_; }
  const std::string& failure() const { return failure_; }
  const std::vector<RetryEvent>& retries() const { return retries_; }
  const std::vector<ResendEvent>& resends() const { return resends_; }
  /// Messages of another run (another Bus::run_id) this clock heard and ignored, and those each
  /// node reported ignoring with its FINISHED report.
  int foreign_ignored() const { return foreign_; }
  const std::map<std::string, int>& nodes_foreign_ignored() const { return node_foreign_; }
  int windows_per_realization() const { return n_windows_; }
  /// [s wall] How long the caller may block before the next poll() has something to do (a
  /// resend, heartbeat or timeout falls due), in (0, 0.05].
  double idle_s(double wall_now_s) const;
  /// [s wall] The current resend wait (adaptive; see RunnerOptions::stall_timeout_s).
  double resend_wait_s() const;

  /// Called after each completed realization: (completed, total, retries so far).
  std::function<void(int, int, int)> on_progress;
  /// Called after each completed window inside a realization: (realizations completed,
  /// counting the current one's completed share, total, retries so far, the current
  /// realization's sim time reached [s] and its end [s]).
  std::function<void(double, int, int, double, double)> on_window;

 private:
  enum class State { kWaitHello, kRunning, kFinishing, kDone };
  void on_ack(const node_ack_t& a);
  void grant();
  void next_window();
  void retry(const std::string& reason);
  void abort(const std::string& reason, int code);
  void send(std::int8_t command, const std::string& reason = "");
  void resend();
  std::string overdue() const;
  void check_silent_nodes();
  void on_window_heard(const void* data, int size);

  Bus& bus_;
  RunnerOptions runner_;
  ConductorOptions o_;
  std::int64_t window_us_, end_us_;
  int n_windows_;
  State state_ = State::kWaitHello;
  std::set<std::string> hello_, acked_;
  int r_ = 0, a_ = 0, w_ = 0;
  double now_s_ = 0, start_wall_s_ = -1, window_wall_s_ = 0, realization_wall_s_ = 0,
         finish_sent_s_ = -1, last_finish_s_ = -1;
  bool window_open_ = false;
  /// Loss reports of the current attempt, joined: a lost message upstream stalls every node
  /// below it, each reporting its own missing input after its stall timeout; the retry waits
  /// half a stall timeout after the first report so the upstream cause is named with them.
  std::string loss_reasons_;
  /// Hashes of every SIM_WINDOW message this clock sent (their bytes). LCM delivers a clock's
  /// own messages back to it; one it did not send comes from another clock on the same network
  /// (another run, a replayed log) and fails the run at once, naming it, instead of as a
  /// missing ack 18 s later.
  std::unordered_set<std::uint64_t> sent_;
  int foreign_ = 0;
  std::map<std::string, int> node_foreign_;
  double loss_deadline_s_ = -1;  ///< [s wall] when the collected losses are acted on (< 0: none)
  std::vector<RetryEvent> retries_;
  std::vector<ResendEvent> resends_;
  // Recovery of the open window: when it last progressed (START, RESEND or a new ack), how many
  // RESENDs it took, and what the nodes answering WAITING said they miss.
  double progress_wall_s_ = 0;
  int window_resends_ = 0;
  /// RESENDs in a row of the open window that no node it waits for answered (acked or said
  /// WAITING): the resend wait doubles with each. An answer shows the network and the nodes alive,
  /// so the wait drops back: under heavy loss a lost republished batch is then asked for again at
  /// the run's pace, and not after an ever longer wait.
  int unanswered_resends_ = 0;
  std::map<std::string, std::string> waiting_;
  // Pace of the run: per window, its slowest ack gap [s wall] that no RESEND interrupted (-1:
  // none), of the last windows.
  std::vector<double> pace_;
  std::size_t pace_next_ = 0;
  double pace_median_s_ = 0;                   // [s wall] their median
  double window_max_gap_s_ = 0;
  bool resent_since_ack_ = false;              // a RESEND since last_ack_wall_s_
  double last_ack_wall_s_ = 0;                 // [s wall] the open window's START or its last new ack
  double last_sent_s_ = -1;                  // [s wall] the clock's last message (for heartbeats)
  std::map<std::string, double> last_heard_; // [s wall] per node: its last message of any kind
  std::map<std::string, int> unanswered_;    // per node: RESENDs sent since its last message
  std::string failure_;
  int exit_code_ = 0;
};

}  // namespace rnav
