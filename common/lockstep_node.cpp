#include "lockstep_node.hpp"

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
    if (parts.size() < 3 || parts.size() > 4) throw std::invalid_argument("parts");
    d.channel = parts[0];
    d.realization = std::stoi(parts[1]);
    d.window = std::stoi(parts[2]);
    if (parts.size() == 4) d.attempt = std::stoi(parts[3]);
  } catch (const std::exception&) {
    throw std::invalid_argument("--drop '" + text + "': expected CHANNEL:REALIZATION:WINDOW[:ATTEMPT]");
  }
  return d;
}

LockstepNode::LockstepNode(Bus& bus, std::string name, double stall_timeout_s)
    : bus_(bus), name_(std::move(name)), stall_timeout_s_(stall_timeout_s) {
  bus_.subscribe<sim_window_t>(ch::kWindow, [this](const sim_window_t& w) { on_grant(w); });
}

bool LockstepNode::dropped(const std::string& channel) const {
  for (const auto& d : drops_)
    if (d.channel == channel && d.realization == grant_.realization && d.window == grant_.window &&
        (d.attempt < 0 || d.attempt == grant_.attempt))
      return true;
  return false;
}

bool LockstepNode::newer(int r, int a) const {
  return r > cur_r_ || (r == cur_r_ && a > cur_a_);
}

void LockstepNode::report(std::int8_t status, const std::string& detail) {
  node_ack_t ack;
  ack.node = name_;
  ack.status = status;
  ack.realization = status == node_ack_t::HELLO ? -1 : cur_r_;
  ack.attempt = status == node_ack_t::HELLO ? -1 : cur_a_;
  ack.window = status == node_ack_t::HELLO ? -1 : grant_.window;
  ack.n_published = published_;
  ack.detail = detail;
  bus_.publish(ch::kAck, ack);
}

void LockstepNode::fail(const std::string& detail) {
  if (failed_ || cur_r_ < 0) return;
  failed_ = true;
  report(node_ack_t::LOSS, name_ + ": " + detail);
}

void LockstepNode::on_grant(const sim_window_t& w) {
  if (done_) return;
  if (w.command == sim_window_t::FINISH) {
    if (processed_any_) commit();
    processed_any_ = false;
    finish(w);
    report(node_ack_t::FINISHED, "");
    done_ = true;
    exit_code_ = 0;
    return;
  }
  if (w.command == sim_window_t::ABORT) {
    done_ = true;
    exit_code_ = 3;
    return;
  }
  if (w.command != sim_window_t::START)
    throw std::runtime_error(name_ + ": unknown SIM_WINDOW command " + std::to_string(w.command));

  started_ = true;
  if (newer(w.realization, w.attempt)) {
    if (processed_any_ && w.realization != cur_r_) commit();
    processed_any_ = false;
    cur_r_ = w.realization;
    cur_a_ = w.attempt;
    next_window_ = 0;
    failed_ = false;
    have_grant_ = false;
    // Forget everything older than the new (realization, attempt).
    for (auto& in : inputs_)
      for (auto it = in->store.begin(); it != in->store.end();)
        it = (std::get<0>(it->first) < cur_r_ ||
              (std::get<0>(it->first) == cur_r_ && std::get<1>(it->first) < cur_a_))
                 ? in->store.erase(it)
                 : std::next(it);
    // A repeated attempt exists because something was lost; what the failed attempt lost is
    // already reported, so the first sequence number of each input is taken as it comes.
    // Loss within the new attempt is still caught by the window checks.
    if (w.attempt > 0)
      for (auto& in : inputs_) in->resync = true;
    grant_ = w;
    reset(w);
  } else if (w.realization != cur_r_ || w.attempt != cur_a_) {
    return;  // a grant of an abandoned attempt
  }
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
  grant_wall_s_ = now_s_;
  try_process();
}

void LockstepNode::on_batch(InputStream& in, const batch_header_t& h,
                            std::shared_ptr<const void> batch) {
  if (done_) return;
  const std::string where = in.channel + " (realization " + std::to_string(h.realization) +
                            ", attempt " + std::to_string(h.attempt) + ", window " +
                            std::to_string(h.window) + ", seq " + std::to_string(h.seq) + ")";
  if (in.resync && h.seq >= in.next_seq) in.next_seq = h.seq;
  in.resync = false;
  if (h.seq != in.next_seq) {
    const std::int64_t expected = in.next_seq;
    in.next_seq = std::max(in.next_seq, h.seq + 1);
    if (h.seq > expected)
      fail(std::to_string(h.seq - expected) + " message(s) lost on " + in.channel +
           ": expected seq " + std::to_string(expected) + ", got " + where);
    else
      fail("duplicate or out-of-order message on " + where + ", expected seq " +
           std::to_string(expected));
    return;
  }
  in.next_seq = h.seq + 1;
  if (cur_r_ >= 0 && !newer(h.realization, h.attempt) &&
      !(h.realization == cur_r_ && h.attempt == cur_a_))
    return;  // a batch of an abandoned attempt: ignore
  const WindowKey key{h.realization, h.attempt, h.window};
  if (in.store.count(key)) {
    fail("duplicate batch on " + where);
    return;
  }
  in.store.emplace(key, std::move(batch));
  try_process();
}

void LockstepNode::try_process() {
  if (!have_grant_ || failed_ || done_) return;
  const WindowKey key{grant_.realization, grant_.attempt, grant_.window};
  for (const auto& in : inputs_)
    if (!in->store.count(key)) return;
  have_grant_ = false;
  published_ = 0;
  try {
    process(grant_);
  } catch (const std::exception& e) {
    report(node_ack_t::ERROR, name_ + ": " + e.what());
    throw;
  }
  processed_any_ = true;
  for (auto& in : inputs_) in->store.erase(key);
  ++next_window_;
  report(node_ack_t::OK, "");
}

void LockstepNode::poll(double wall_now_s) {
  now_s_ = wall_now_s;
  if (done_) return;
  if (!started_ && wall_now_s - last_hello_s_ >= 0.2) {
    last_hello_s_ = wall_now_s;
    report(node_ack_t::HELLO, "");
  }
  if (have_grant_ && !failed_ && wall_now_s - grant_wall_s_ > stall_timeout_s_) {
    const WindowKey key{grant_.realization, grant_.attempt, grant_.window};
    std::string missing;
    for (const auto& in : inputs_)
      if (!in->store.count(key))
        missing += (missing.empty() ? "" : ", ") + in->channel + " (next seq " +
                   std::to_string(in->next_seq) + ")";
    fail("no batch for realization " + std::to_string(grant_.realization) + " attempt " +
         std::to_string(grant_.attempt) + " window " + std::to_string(grant_.window) + " on " +
         missing + " after " + std::to_string(stall_timeout_s_) + " s: lost");
  }
}

}  // namespace rnav
