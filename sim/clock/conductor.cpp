#include "sim/clock/conductor.hpp"

#include "common/node/channels.hpp"
#include "common/node/lockstep_node.hpp"

#include <rnav/sim_scenario_t.hpp>
#include <rnav/sim_window_t.hpp>

#include <algorithm>
#include <cmath>

#include <limits>

namespace rnav {

Conductor::Conductor(Bus& bus, const RunnerOptions& runner, double step_s,
                     const ConductorOptions& o, double duration_s)
    : bus_(bus), runner_(runner), o_(o) {
  if (o.n_realizations < 1) throw ConfigError("--realizations must be >= 1");
  if (o.first_realization < 0 || o.first_realization > std::numeric_limits<std::int32_t>::max() - o.n_realizations)
    throw ConfigError("--first-realization must be in 0 ... 2^31-1 - realizations, got " + std::to_string(o.first_realization));
  r_ = o.first_realization;
  if (o.nodes.empty()) throw ConfigError("the clock needs the list of nodes (--nodes)");
  if (!(o.speed > 0)) throw ConfigError("--speed must be > 0");
  const std::int64_t step = to_us(step_s);
  // The realization spans the trajectory plus the flush time, on the truth grid.
  const std::int64_t raw_end = to_us(duration_s + runner.flush_s);
  end_us_ = (raw_end + step - 1) / step * step;
  // runner.window_s = 0: the whole realization is one window.
  window_us_ = runner.window_s > 0 ? to_us(runner.window_s) : end_us_;
  if (window_us_ <= 0) throw ConfigError("the clock needs a realization longer than 0 s (runner.window_s, flush_s)");
  n_windows_ = static_cast<int>((end_us_ + window_us_ - 1) / window_us_);
  bus_.subscribe<node_ack_t>(ch::kAck, [this](const node_ack_t& a) { on_ack(a); });
  bus_.subscribe_raw(ch::kWindow, [this](const std::string&, const void* data, int size) { on_window_heard(data, size); });
}

// its own messages are known by message_digest (lockstep_node.hpp), taken before each is sent
void Conductor::on_window_heard(const void* data, int size) {
  if (state_ == State::kDone || sent_.count(message_digest(data, size))) return;
  sim_window_t w;
  const bool decoded = w.decode(data, 0, size) == size;
  if (decoded && w.run_id != bus_.run_id()) {  // another run's clock on this network: not ours to obey
    ++foreign_;
    return;
  }
  // of this run, yet not sent by this clock: a second clock of the same run id (or a forged one)
  abort("foreign traffic on " + std::string(ch::kWindow) + ": a message this clock did not send" +
            (decoded ? " (command " + std::to_string(w.command) + ", seed " + std::to_string(w.seed) + ", " +
                           std::to_string(w.n_realizations) + " realization(s), realization " + std::to_string(w.realization) +
                           ", window " + std::to_string(w.window) + "; this run: seed " + std::to_string(o_.seed) + ", " +
                           std::to_string(o_.n_realizations) + ")"
                     : " (" + std::to_string(size) + " bytes that do not decode as sim_window_t)") +
            ": another run or a replayed log shares this LCM network; give each run its own "
            "(scripts/run --net netns) or another --lcm-url",
        4);
}

void Conductor::send(std::int8_t command, const std::string& reason) {
  sim_window_t w;
  w.command = command;
  w.seed = o_.seed;
  w.n_realizations = o_.n_realizations;
  w.realization = r_;
  w.attempt = a_;
  w.window = w_;
  w.last_window = w_ == n_windows_ - 1;
  const std::int64_t b = static_cast<std::int64_t>(w_) * window_us_;
  w.utime_begin = (runner_.epoch_utime + b);
  w.utime_end = (runner_.epoch_utime + std::min(b + window_us_, end_us_));
  w.reason = reason;
  w.run_id = bus_.run_id();
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(w.getEncodedSize()));
  w.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  sent_.insert(message_digest(bytes.data(), static_cast<int>(bytes.size())));  // before it can come back
  bus_.publish_raw(ch::kWindow, bytes.data(), static_cast<int>(bytes.size()));
  last_sent_s_ = now_s_;
}

namespace {
constexpr std::size_t kPaceWindows = 32;   // windows the resend wait learns the run's pace from
constexpr double kPaceFactor = 2;          // resend after this many times the median recent ack gap
constexpr double kMinResendWaitS = 0.001;  // [s wall] never sooner (scheduling jitter)
constexpr double kFirstResendWaitS = 0.05; // [s wall] before any pace is known
constexpr double kRealtimeResendShare = 0.5;  // real time: resend after this share of a window's wall time
constexpr double kHeartbeatsPerTimeout = 8;
constexpr double kFinishRepeatS = 0.05;    // [s wall] FINISH is repeated until every node reports FINISHED
constexpr int kCloseCopies = 3;            // CLOSE is sent this many times (nodes exit on the first)
}  // namespace

double Conductor::resend_wait_s() const {
  double wait = kFirstResendWaitS;
  // wait = max(1 ms, 2 x the median of the last windows' slowest ack gaps)
  if (!pace_.empty()) wait = std::max(kMinResendWaitS, kPaceFactor * pace_median_s_);
  // Real time has slack until the next window is due: resend only after half a window's wall
  // time (a resend at the batch pace would publish copies a viewer counts as messages).
  if (o_.realtime) wait = std::max(wait, kRealtimeResendShare * window_us_ * 1e-6 / o_.speed);
  // Each RESEND in a row that no overdue node answered doubles the wait (a slow node is not
  // flooded); an answer resets it. (Doubling on every RESEND of the window, as before, gave a
  // heavy tail under 20 % loss: a 160 kB batch is three datagrams, each RESEND round failed with
  // probability about one half, and P(k failures) 2^k does not fall.)
  wait *= std::pow(2.0, std::min(unanswered_resends_, 20));
  return std::min(wait, runner_.stall_timeout_s);
}

double Conductor::idle_s(double wall_now_s) const {
  double due = wall_now_s + 0.05;
  if (state_ == State::kRunning && window_open_) due = std::min(due, progress_wall_s_ + resend_wait_s());
  if (loss_deadline_s_ >= 0) due = std::min(due, loss_deadline_s_);
  due = std::min(due, last_sent_s_ + runner_.peer_timeout_s / kHeartbeatsPerTimeout);
  return std::clamp(due - wall_now_s, 0.001, 0.05);
}

std::string Conductor::overdue() const {
  std::string s;
  for (const auto& n : o_.nodes)
    if (!acked_.count(n)) {
      const auto w = waiting_.find(n);
      s += (s.empty() ? "" : "; ") + (w != waiting_.end() ? w->second : n + ": no ack");
    }
  return s;
}

void Conductor::resend() {
  const std::string why = overdue();
  resends_.push_back({r_, a_, w_, why, now_s_ - start_wall_s_, now_s_ - progress_wall_s_});
  for (const auto& n : o_.nodes)
    if (!acked_.count(n)) ++unanswered_[n];
  ++window_resends_;
  ++unanswered_resends_;
  progress_wall_s_ = now_s_;
  resent_since_ack_ = true;
  send(sim_window_t::RESEND, why);
}

void Conductor::check_silent_nodes() {
  // A node the open window waits for, heard from neither since the window's START nor within
  // peer_timeout_s: it is frozen or gone (a live node answers every RESEND).
  for (const auto& n : o_.nodes) {
    if (acked_.count(n)) continue;
    const auto it = last_heard_.find(n);
    const double heard = std::max(it == last_heard_.end() ? start_wall_s_ : it->second, window_wall_s_);
    const auto un = unanswered_.find(n);
    if (un != unanswered_.end() && un->second >= 2 && now_s_ - heard > runner_.peer_timeout_s) {
      abort("node '" + n + "' fell silent: no ack and no answer to " + std::to_string(un->second) +
                " RESEND(s) for " + std::to_string(now_s_ - heard) + " s (runner.peer_timeout_s " +
                std::to_string(runner_.peer_timeout_s) + ") at realization " + std::to_string(r_) + " attempt " +
                std::to_string(a_) + " window " + std::to_string(w_) + ": frozen or dead",
            4);
      return;
    }
  }
}

void Conductor::grant() {
  acked_.clear();
  waiting_.clear();
  window_open_ = true;
  window_wall_s_ = progress_wall_s_ = last_ack_wall_s_ = now_s_;
  window_resends_ = unanswered_resends_ = 0;
  window_max_gap_s_ = -1;
  resent_since_ack_ = false;
  if (w_ == 0) realization_wall_s_ = now_s_;
  if (w_ == 0 && !o_.scenario_json.empty()) {
    sim_scenario_t s;
    s.realization = r_;
    s.attempt = a_;
    s.kind = o_.scenario_kind;
    s.source = o_.scenario_source;
    s.scenario_json = o_.scenario_json;
    bus_.publish(ch::kScenario, s);
  }
  send(sim_window_t::START);
}

void Conductor::next_window() {
  window_open_ = false;
  // Learn the pace from the ack gaps no RESEND interrupted (one that did holds a resend wait:
  // learning it would make the wait grow with itself under heavy loss), as the median of the
  // windows' slowest such gap. (The slowest gap of windows without any resend, as before,
  // ratcheted the wait down: a window slower than the wait got a resend and was never learnt,
  // and every other window of a clean run was resent.)
  if (window_max_gap_s_ >= 0) {
    if (pace_.size() < kPaceWindows) pace_.push_back(window_max_gap_s_);
    else pace_[pace_next_] = window_max_gap_s_;
    pace_next_ = (pace_next_ + 1) % kPaceWindows;
    std::vector<double> g(pace_);
    std::nth_element(g.begin(), g.begin() + static_cast<std::ptrdiff_t>(g.size() / 2), g.end());
    pace_median_s_ = g[g.size() / 2];
  }
  if (w_ + 1 < n_windows_) {
    ++w_;
    if (on_window) {
      const double share = static_cast<double>(w_) / n_windows_;
      on_window(r_ - o_.first_realization + share, o_.n_realizations, static_cast<int>(retries_.size()),
                static_cast<double>(static_cast<std::int64_t>(w_) * window_us_) * 1e-6,
                static_cast<double>(end_us_) * 1e-6);
    }
  } else {
    const int done = r_ - o_.first_realization + 1;
    if (on_progress) on_progress(done, o_.n_realizations, static_cast<int>(retries_.size()));
    if (done >= o_.n_realizations) {
      state_ = State::kFinishing;
      acked_.clear();
      finish_sent_s_ = last_finish_s_ = now_s_;
      send(sim_window_t::FINISH);
      return;
    }
    ++r_;
    a_ = 0;
    w_ = 0;
  }
  if (!o_.realtime) grant();  // realtime: poll() grants when the wall clock gets there
}

void Conductor::retry(const std::string& reason) {
  retries_.push_back({r_, a_, reason});
  loss_reasons_.clear();
  loss_deadline_s_ = -1;
  window_open_ = false;
  if (a_ + 1 >= runner_.max_attempts) {
    std::string all;
    for (const auto& e : retries_)
      if (e.realization == r_) all += "\n  attempt " + std::to_string(e.attempt) + ": " + e.reason;
    abort("realization " + std::to_string(r_) + " failed " + std::to_string(a_ + 1) +
              " times (runner.max_attempts):" + all,
          3);
    return;
  }
  ++a_;
  w_ = 0;
  grant();
}

void Conductor::abort(const std::string& reason, int code) {
  failure_ = reason;
  exit_code_ = code;
  state_ = State::kDone;
  for (int i = 0; i < 3; ++i) send(sim_window_t::ABORT, reason);
}

void Conductor::on_ack(const node_ack_t& a) {
  if (state_ == State::kDone) return;
  if (a.run_id != bus_.run_id()) {  // another run's node on this network
    ++foreign_;
    return;
  }
  if (std::find(o_.nodes.begin(), o_.nodes.end(), a.node) == o_.nodes.end()) {
    // an ack counted toward a window it does not belong to would close it early
    std::string ours;
    for (const auto& n : o_.nodes) ours += (ours.empty() ? "" : ", ") + n;
    abort("foreign traffic on " + std::string(ch::kAck) + ": node '" + a.node + "' is not one of this run's nodes (" + ours +
              "): another run or a replayed log shares this LCM network; give each run its own "
              "(scripts/run --net netns) or another --lcm-url",
          4);
    return;
  }
  last_heard_[a.node] = now_s_;
  unanswered_[a.node] = 0;
  if (a.status == node_ack_t::HELLO) {
    hello_.insert(a.node);
    return;
  }
  if (state_ == State::kFinishing) {
    if (a.status == node_ack_t::FINISHED) {
      acked_.insert(a.node);
      node_foreign_[a.node] = a.n_foreign;
    }
    if (acked_.size() == o_.nodes.size()) {
      state_ = State::kDone;
      // Every node has finished: let them go now instead of after their linger. Sent three times
      // (a CLOSE lost everywhere only costs the linger).
      for (int i = 0; i < kCloseCopies; ++i) send(sim_window_t::CLOSE);
    }
    return;
  }
  if (state_ != State::kRunning || a.realization != r_ || a.attempt != a_) return;  // stale
  if (a.status == node_ack_t::ERROR) {
    abort("node " + a.node + " failed: " + a.detail, 4);
    return;
  }
  if (a.status == node_ack_t::LOSS) {
    if (window_open_ || a.window <= w_) {
      loss_reasons_ += (loss_reasons_.empty() ? "" : "; ") + a.detail;
      if (loss_deadline_s_ < 0) loss_deadline_s_ = now_s_ + runner_.stall_timeout_s / 2;
    }
    return;
  }
  if (a.status == node_ack_t::WAITING) {
    if (window_open_ && a.window == w_) {
      waiting_[a.node] = a.detail;
      unanswered_resends_ = 0;
    }
    return;
  }
  if (a.status == node_ack_t::OK && window_open_ && a.window == w_ && !acked_.count(a.node)) {
    acked_.insert(a.node);
    unanswered_resends_ = 0;
    waiting_.erase(a.node);
    if (!resent_since_ack_) window_max_gap_s_ = std::max(window_max_gap_s_, now_s_ - last_ack_wall_s_);
    resent_since_ack_ = false;
    progress_wall_s_ = last_ack_wall_s_ = now_s_;
    if (acked_.size() == o_.nodes.size()) next_window();
  }
}

void Conductor::poll(double wall_now_s) {
  now_s_ = wall_now_s;
  if (start_wall_s_ < 0) start_wall_s_ = wall_now_s;
  switch (state_) {
    case State::kWaitHello: {
      bool all = true;
      std::string missing;
      for (const auto& n : o_.nodes)
        if (!hello_.count(n)) {
          all = false;
          missing += " " + n;
        }
      if (all) {
        state_ = State::kRunning;
        realization_wall_s_ = now_s_;
        if (!o_.realtime) grant();
      } else if (now_s_ - start_wall_s_ > o_.hello_timeout_s) {
        abort("these nodes never reported ready within " + std::to_string(o_.hello_timeout_s) +
                  " s:" + missing,
              4);
      }
      break;
    }
    case State::kRunning:
      if (window_open_) check_silent_nodes();
      if (state_ != State::kRunning) break;
      if (loss_deadline_s_ >= 0 && now_s_ >= loss_deadline_s_) {
        retry(loss_reasons_);
      } else if (window_open_ && now_s_ - window_wall_s_ > runner_.ack_timeout_s) {
        retry("window not complete within " + std::to_string(runner_.ack_timeout_s) + " s (runner.ack_timeout_s) for realization " +
              std::to_string(r_) + " attempt " + std::to_string(a_) + " window " + std::to_string(w_) + " after " +
              std::to_string(window_resends_) + " RESEND(s): " + overdue());
      } else if (window_open_ && now_s_ - progress_wall_s_ > resend_wait_s()) {
        resend();
      } else if (o_.realtime && !window_open_) {
        // Window w starts when the wall clock reaches its sim start time.
        const double due = realization_wall_s_ + (w_ * window_us_ * 1e-6) / o_.speed;
        if (now_s_ >= due) grant();
      }
      break;
    case State::kFinishing:
      if (now_s_ - finish_sent_s_ > runner_.ack_timeout_s) {
        std::string missing;
        for (const auto& n : o_.nodes)
          if (!acked_.count(n)) missing += " " + n;
        failure_ = "no FINISHED report from:" + missing;
        exit_code_ = 4;
        state_ = State::kDone;
      } else if (now_s_ - last_finish_s_ > kFinishRepeatS) {
        last_finish_s_ = now_s_;
        send(sim_window_t::FINISH);  // repeated: a lost FINISH must not hang the run
      }
      break;
    case State::kDone:
      break;
  }
  if (state_ != State::kDone && now_s_ - last_sent_s_ >= runner_.peer_timeout_s / kHeartbeatsPerTimeout)
    send(sim_window_t::HEARTBEAT);
}

}  // namespace rnav
