#include "common/node/lockstep_node.hpp"

#include "common/io/config.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace rnav {

DropSpec DropSpec::parse(const std::string& text) {
  DropSpec d;
  std::stringstream ss(text);
  std::string part;
  std::vector<std::string> parts;
  while (std::getline(ss, part, ':')) parts.push_back(part);
  try {
    if (parts.size() < 3 || parts.size() > 5) throw std::invalid_argument("parts");
    auto number = [](const std::string& t) {
      std::size_t pos = 0;
      const int v = std::stoi(t, &pos);
      if (pos != t.size() || v < 0) throw std::invalid_argument(t);
      return v;
    };
    d.channel = parts[0];
    d.realization = number(parts[1]);
    d.window = number(parts[2]);
    if (parts.size() >= 4) d.attempt = number(parts[3]);
    if (parts.size() == 5) d.transmissions = number(parts[4]);
    if (d.transmissions == 0) throw std::invalid_argument("K");
  } catch (const std::exception&) {
    throw ConfigError("--drop '" + text +
                                "': expected CHANNEL:REALIZATION:WINDOW[:ATTEMPT[:K]] (non-negative integers, K >= 1)");
  }
  return d;
}

std::uint64_t message_digest(const void* data, int size) {
  // FNV-1a's scheme over 8-byte words (eight times fewer steps than per byte), each word mixed
  // by a rotate before the multiply; then the tail bytes. Not cryptographic: it tells a resend
  // from a different batch, which no adversary chooses.
  std::uint64_t h = 14695981039346656037ULL ^ static_cast<std::uint64_t>(size);
  const auto* p = static_cast<const std::uint8_t*>(data);
  int i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = (h ^ w) * 1099511628211ULL;
    h ^= h >> 29;
  }
  for (; i < size; ++i) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

LockstepNode::LockstepNode(Bus& bus, std::string name, double peer_timeout_s)
    : bus_(bus), name_(std::move(name)), peer_timeout_s_(peer_timeout_s) {
  if (!(peer_timeout_s_ > 0)) throw std::invalid_argument(name_ + ": the peer timeout must be > 0 s");
  bus_.subscribe<sim_window_t>(ch::kWindow, [this](const sim_window_t& w) { on_grant(w); });
  bus_.subscribe<node_ack_t>(ch::kAck, [this](const node_ack_t& a) { on_peer_ack(a); });
}

Wire parse_wire(const std::string& text) {
  if (text == "batch") return Wire::kBatch;
  if (text == "sample") return Wire::kSample;
  throw std::invalid_argument("runner.wire must be \"batch\" or \"sample\", got \"" + text + "\"");
}

void LockstepNode::transmit(const Output& out) {
  const WindowKey key = last_out_key_;  // the window being processed, or the last one (a resend)
  const int k = ++transmissions_[{out.channel, key}];
  for (const auto& d : drops_)
    if (d.channel == out.channel && d.realization == std::get<0>(key) && d.window == std::get<2>(key) &&
        (d.attempt < 0 || d.attempt == std::get<1>(key)) && (d.transmissions < 0 || k <= d.transmissions))
      return;  // fault injection: this transmission (the batch, or all samples of the window) is lost
  for (const auto& m : out.messages) bus_.publish_raw(out.channel, m.data(), static_cast<int>(m.size()));
}

bool LockstepNode::newer(int r, int a) const {
  return r > cur_r_ || (r == cur_r_ && a > cur_a_);
}

void LockstepNode::report(std::int8_t status, const std::string& detail, const std::vector<std::string>& missing,
                          std::optional<int> window) {
  node_ack_t ack;
  ack.node = name_;
  ack.status = status;
  ack.realization = status == node_ack_t::HELLO ? -1 : cur_r_;
  ack.attempt = status == node_ack_t::HELLO ? -1 : cur_a_;
  ack.window = status == node_ack_t::HELLO ? -1 : window.value_or(grant_.window);
  ack.n_published = published_;
  ack.detail = detail;
  ack.n_missing = static_cast<std::int16_t>(missing.size());
  ack.missing = missing;
  if (status == node_ack_t::OK)
    for (const auto& out : last_out_) {
      ack.published.push_back(out.channel);
      ack.published_n.push_back(out.n_samples);
      if (wire_ == Wire::kSample)
        for (const auto& m : out.messages)
          ack.sample_digests.push_back(static_cast<std::int64_t>(message_digest(m.data(), static_cast<int>(m.size()))));
    }
  ack.n_published_channels = static_cast<std::int16_t>(ack.published.size());
  ack.n_sample_digests = static_cast<std::int32_t>(ack.sample_digests.size());
  ack.run_id = bus_.run_id();
  ack.n_foreign = foreign_;
  bus_.publish(ch::kAck, ack);
}

void LockstepNode::fail(const std::string& detail) {
  if (failed_ || cur_r_ < 0) return;
  failed_ = true;
  failed_detail_ = name_ + ": " + detail;
  report(node_ack_t::LOSS, failed_detail_);
}

void LockstepNode::stop(int code, const std::string& why) {
  done_ = true;
  exit_code_ = code;
  failure_ = why;
}

std::optional<WindowKey> LockstepNode::needed_key(const InputStream& in) const {
  if (grant_.window - in.delay < 0) return std::nullopt;
  return WindowKey{grant_.realization, grant_.attempt, grant_.window - in.delay};
}

bool LockstepNode::holds_needed(const InputStream& in) const {
  const auto key = needed_key(in);
  return !key || in.store.count(*key) > 0;
}

std::vector<std::string> LockstepNode::missing_inputs() const {
  std::vector<std::string> missing;
  for (const auto& in : inputs_)
    if (!holds_needed(*in)) missing.push_back(in->channel);
  return missing;
}

void LockstepNode::begin_attempt(const sim_window_t& w) {
  if (processed_any_ && w.realization != cur_r_) commit();
  processed_any_ = false;
  cur_r_ = w.realization;
  cur_a_ = w.attempt;
  next_window_ = 0;
  failed_ = false;
  failed_detail_.clear();
  have_grant_ = false;
  last_out_.clear();
  last_out_key_ = {-1, -1, -1};
  transmissions_.clear();
  // Forget everything older than the new (realization, attempt).
  auto older = [&](const WindowKey& k) {
    return std::get<0>(k) < cur_r_ || (std::get<0>(k) == cur_r_ && std::get<1>(k) < cur_a_);
  };
  for (auto& in : inputs_) {
    in->inbox.clear();  // samples of the abandoned attempt (a sample of the new one here early is asked for again)
    for (auto it = in->expected.begin(); it != in->expected.end();) it = older(it->first) ? in->expected.erase(it) : std::next(it);
    for (auto it = in->store.begin(); it != in->store.end();) it = older(it->first) ? in->store.erase(it) : std::next(it);
    for (auto it = in->digest.begin(); it != in->digest.end();) it = older(it->first) ? in->digest.erase(it) : std::next(it);
  }
  // A repeated attempt exists because something was lost; what the failed attempt lost is
  // already reported, so the first sequence number of each input is taken as it comes.
  // Loss within the new attempt is still caught by the window checks.
  if (w.attempt > 0)
    for (auto& in : inputs_) in->resync = true;
  grant_ = w;
  reset(w);
}

void LockstepNode::accept_grant(const sim_window_t& w) {
  grant_ = w;
  if (failed_) return;
  if (w.window != next_window_) {
    fail("SIM_WINDOW for realization " + std::to_string(w.realization) + " attempt " +
         std::to_string(w.attempt) + ": got window " + std::to_string(w.window) + ", expected " +
         std::to_string(next_window_) +
         (w.window > next_window_ ? " (a grant was lost)" : " (duplicate or out of order)"));
    return;
  }
  have_grant_ = true;
  try_process();
}

void LockstepNode::on_grant(const sim_window_t& w) {
  if (done_) return;
  if (w.run_id != bus_.run_id()) {  // another run's clock on this network
    ++foreign_;
    return;
  }
  clock_heard_ = true;  // timed at the next poll()
  if (finished_ && w.command == sim_window_t::CLOSE) {
    stop(0, "");  // every node has finished: no FINISH will be repeated
    return;
  }
  if (finished_ && w.command != sim_window_t::FINISH) return;
  switch (w.command) {
    case sim_window_t::HEARTBEAT:
      // The clock has started (it speaks first with a heartbeat, and again every
      // peer_timeout_s / 8 while it waits): answer each at once, not at the next periodic HELLO
      // (a HELLO sent before the clock was listening is lost).
      if (!started_) {
        last_hello_s_ = now_s_;
        report(node_ack_t::HELLO, "");
      }
      return;
    case sim_window_t::CLOSE:
      return;  // not finished: the FINISH is on its way (CLOSE follows every FINISHED)
    case sim_window_t::FINISH:
      if (!finished_) {
        if (processed_any_) commit();
        processed_any_ = false;
        finish(w);
        finished_ = true;
      }
      // Repeated FINISH: the FINISHED report was lost. The node lingers to answer (poll()).
      report(node_ack_t::FINISHED, "");
      return;
    case sim_window_t::ABORT:
      stop(3, "aborted by the clock: " + w.reason);
      return;
    case sim_window_t::RESEND:
      on_resend(w);
      return;
    case sim_window_t::START:
      break;
    default:
      throw std::runtime_error(name_ + ": unknown SIM_WINDOW command " + std::to_string(w.command));
  }
  started_ = true;
  if (newer(w.realization, w.attempt)) {
    begin_attempt(w);
  } else if (w.realization != cur_r_ || w.attempt != cur_a_) {
    return;  // a grant of an abandoned attempt
  } else if (w.window < next_window_ && w.window == std::get<2>(last_out_key_)) {
    return;  // the START of a window already processed, repeated: the RESEND path answers
  }
  accept_grant(w);
}

void LockstepNode::on_resend(const sim_window_t& w) {
  if (newer(w.realization, w.attempt)) {
    // The START of a new attempt was lost; the RESEND carries the same grant.
    started_ = true;
    begin_attempt(w);
    accept_grant(w);
    return;
  }
  if (w.realization != cur_r_ || w.attempt != cur_a_) return;  // an abandoned attempt
  if (failed_) {
    report(node_ack_t::LOSS, failed_detail_);  // the LOSS report itself may have been lost
    return;
  }
  if (w.window == next_window_ - 1) {
    report(node_ack_t::OK, "");  // processed: the ack was lost (or a consumer's input: see on_peer_ack)
  } else if (w.window == next_window_ && !have_grant_) {
    accept_grant(w);  // its START was lost
  } else if (w.window == next_window_) {
    report_waiting(missing_inputs());
  } else {
    fail("RESEND of window " + std::to_string(w.window) + " while at window " + std::to_string(next_window_) +
         " (grants lost or out of order)");
  }
}

void LockstepNode::report_waiting(const std::vector<std::string>& missing) {
  // One WAITING per window asked for: this window's inputs, and the window before for feedback inputs.
  for (const int delay : {0, 1}) {
    std::vector<std::string> part;
    for (const auto& m : missing)
      for (const auto& in : inputs_)
        if (in->channel == m && in->delay == delay) part.push_back(m);
    if (part.empty()) continue;
    const int w = grant_.window - delay;
    std::string detail = name_ + ": waiting for realization " + std::to_string(grant_.realization) + " attempt " +
                         std::to_string(grant_.attempt) + " window " + std::to_string(w) + " on";
    for (const auto& m : part) detail += " " + m;
    report(node_ack_t::WAITING, detail, part, w);
  }
}

void LockstepNode::on_peer_ack(const node_ack_t& a) {
  if (done_ || a.node == name_) return;
  if (a.run_id != bus_.run_id()) {  // another run's node
    ++foreign_;
    return;
  }
  const WindowKey key{a.realization, a.attempt, a.window};
  if (a.status == node_ack_t::WAITING && key == last_out_key_) {
    // A consumer misses a batch of the last window this node processed: publish it again.
    for (const auto& m : a.missing)
      for (const auto& out : last_out_)
        if (out.channel == m) {
          transmit(out);
          ++republished_;
        }
    return;
  }
  if (a.status != node_ack_t::OK) return;
  // Only for a window still to come: an ack repeated for a processed window (a RESEND's answer)
  // must not assemble it again from late copies.
  // (A feedback input takes the window before the one to come.)
  auto to_come = [&](const InputStream& in) {
    return newer(a.realization, a.attempt) ||
           (a.realization == cur_r_ && a.attempt == cur_a_ && a.window >= next_window_ - in.delay);
  };
  if (wire_ == Wire::kSample && !failed_) {
    // The publisher's list of what it sent in that window: assemble the batch from the samples.
    if (a.published_n.size() != a.published.size())
      throw std::runtime_error(name_ + ": malformed ack of " + a.node + " (published_n and published differ in length)");
    std::size_t first = 0;
    for (std::size_t c = 0; c < a.published.size(); ++c) {
      const std::size_t n = static_cast<std::size_t>(std::max(0, a.published_n[c]));
      if (first + n > a.sample_digests.size())
        throw std::runtime_error(name_ + ": malformed ack of " + a.node + " (fewer sample digests than samples)");
      for (auto& in : inputs_)
        if (in->channel == a.published[c] && to_come(*in) && !in->store.count(key)) {
          in->expected[key].assign(a.sample_digests.begin() + static_cast<std::ptrdiff_t>(first),
                                   a.sample_digests.begin() + static_cast<std::ptrdiff_t>(first + n));
          try_assemble(*in);
        }
      first += n;
    }
  }
  if (have_grant_ && !failed_) {
    // A publisher acked a window this node waits on: what it published and is not here was lost.
    std::vector<std::string> lost;
    for (const auto& in : inputs_)
      if (needed_key(*in) == key && !in->store.count(key) &&
          std::find(a.published.begin(), a.published.end(), in->channel) != a.published.end())
        lost.push_back(in->channel);
    if (!lost.empty()) report_waiting(lost);
  }
}

void LockstepNode::on_batch(InputStream& in, const batch_header_t& h, std::shared_ptr<const void> batch,
                            std::uint64_t digest) {
  if (done_) return;
  if (cur_r_ >= 0 && !newer(h.realization, h.attempt) && !(h.realization == cur_r_ && h.attempt == cur_a_))
    return;  // a batch of an abandoned attempt (or its resend): ignore
  const std::string where = in.channel + " (realization " + std::to_string(h.realization) +
                            ", attempt " + std::to_string(h.attempt) + ", window " +
                            std::to_string(h.window) + ", seq " + std::to_string(h.seq) + ")";
  const WindowKey key{h.realization, h.attempt, h.window};
  if (const auto seen = in.digest.find(key); seen != in.digest.end()) {
    if (seen->second != digest)
      throw std::runtime_error(name_ + ": two different batches for one window on " + where +
                               ": a publisher is not deterministic or the message is corrupt");
    ++duplicates_ignored_;  // a resend of what is here already
    return;
  }
  if (in.resync && h.seq >= in.next_seq) in.next_seq = h.seq;
  in.resync = false;
  if (h.seq != in.next_seq) {
    const std::int64_t expected = in.next_seq;
    in.next_seq = std::max(in.next_seq, h.seq + 1);
    if (h.seq > expected)
      fail(std::to_string(h.seq - expected) + " message(s) lost on " + in.channel +
           ": expected seq " + std::to_string(expected) + ", got " + where);
    else
      fail("out-of-order message on " + where + ", expected seq " + std::to_string(expected));
    return;
  }
  in.next_seq = h.seq + 1;
  in.digest.emplace(key, digest);
  in.store.emplace(key, std::move(batch));
  try_process();
}

void LockstepNode::on_sample(InputStream& in, std::uint64_t digest, std::shared_ptr<const void> sample) {
  if (done_) return;
  if (!in.inbox.emplace(digest, std::move(sample)).second) ++duplicates_ignored_;  // a copy of one held
  try_assemble(in);
}

void LockstepNode::try_assemble(InputStream& in) {
  for (auto it = in.expected.begin(); it != in.expected.end();) {
    const WindowKey key = it->first;
    if (in.store.count(key)) {
      it = in.expected.erase(it);
      continue;
    }
    std::vector<std::shared_ptr<const void>> samples;
    for (const std::int64_t d : it->second) {
      const auto s = in.inbox.find(static_cast<std::uint64_t>(d));
      if (s == in.inbox.end()) break;
      samples.push_back(s->second);
    }
    if (samples.size() < it->second.size()) {
      ++it;
      continue;  // not all here yet
    }
    // Everything held was published for this window or earlier (a publisher gets the next grant
    // only once this node acked this window): what is left over are copies.
    in.inbox.clear();
    in.store.emplace(key, in.assemble(samples, key));
    it = in.expected.erase(it);
    try_process();
  }
}

void LockstepNode::try_process() {
  if (!have_grant_ || failed_ || done_) return;
  const WindowKey key{grant_.realization, grant_.attempt, grant_.window};
  for (const auto& in : inputs_)
    if (!holds_needed(*in)) return;
  have_grant_ = false;
  published_ = 0;
  last_out_.clear();
  last_out_key_ = key;
  try {
    process(grant_);
  } catch (const std::exception& e) {
    report(node_ack_t::ERROR, name_ + ": " + e.what());
    throw;
  }
  processed_any_ = true;
  for (auto& in : inputs_)
    if (const auto used = needed_key(*in)) {
      in->store.erase(*used);
      in->expected.erase(*used);
    }
  ++next_window_;
  report(node_ack_t::OK, "");
}

void LockstepNode::poll(double wall_now_s) {
  now_s_ = wall_now_s;
  if (first_poll_s_ < 0) first_poll_s_ = wall_now_s;
  if (done_) return;
  if (finished_) {
    if (finished_at_s_ < 0) finished_at_s_ = wall_now_s;
    if (wall_now_s - finished_at_s_ >= kFinishLingerS) stop(0, "");
    return;
  }
  if (!started_ && wall_now_s - last_hello_s_ >= 0.2) {
    last_hello_s_ = wall_now_s;
    report(node_ack_t::HELLO, "");
  }
  // Watchdog: the clock speaks at least every peer_timeout / 8 (grants, resends, heartbeats).
  if (clock_heard_) last_clock_s_ = wall_now_s;
  clock_heard_ = false;
  if (!clock_watchdog_) return;
  if (last_clock_s_ < 0 && wall_now_s - first_poll_s_ > kClockStartupTimeoutS)
    stop(kClockSilentExit, "never heard the clock (no SIM_WINDOW message) within " +
                               std::to_string(kClockStartupTimeoutS) + " s of start: is rnav_clock running on this LCM network?");
  else if (last_clock_s_ >= 0 && wall_now_s - last_clock_s_ > peer_timeout_s_)
    stop(kClockSilentExit, "the clock fell silent: no SIM_WINDOW message for " + std::to_string(wall_now_s - last_clock_s_) +
                               " s (runner.peer_timeout_s " + std::to_string(peer_timeout_s_) +
                               "; last grant: realization " + std::to_string(grant_.realization) + " attempt " +
                               std::to_string(grant_.attempt) + " window " + std::to_string(grant_.window) + ")");
}

}  // namespace rnav
