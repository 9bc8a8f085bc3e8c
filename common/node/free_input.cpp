#include "common/node/free_input.hpp"

#include "common/node/lockstep_node.hpp"  // message_digest

namespace rnav {

std::int64_t message_fingerprint(const void* data, int size) {
  if (size < 8) return 0;
  const auto* p = static_cast<const std::uint8_t*>(data);
  std::uint64_t f = 0;
  for (int i = 0; i < 8; ++i) f = (f << 8) | p[i];
  return static_cast<std::int64_t>(f);
}

BatchOrder::Step BatchOrder::see(const batch_header_t& h) {
  const FlightKey key{h.realization, h.attempt};
  const auto where = [&] {
    return channel_ + " (realization " + std::to_string(h.realization) + ", attempt " +
           std::to_string(h.attempt) + ", window " + std::to_string(h.window) + ", seq " +
           std::to_string(h.seq) + ")";
  };
  if (h.window < 0 || h.realization < 0 || h.attempt < 0 || h.seq < 0)
    throw std::runtime_error("a batch with a negative index on " + where());
  if (any_ && key < flight_) return Step::kStale;
  if (!any_ || key > flight_) {
    // A new flight: its first window, and seq continuing the publisher's counter.
    if (h.window != 0)
      throw std::runtime_error("a flight's first batch is not window 0 on " + where() +
                               ": its earlier windows were lost");
    // The publisher's seq runs on across flights: a new realization follows a complete one,
    // so its seq continues exactly; a repeated attempt may follow batches lost in the failed one.
    if (any_ && (h.attempt == 0 ? h.seq != next_seq_ : h.seq < next_seq_))
      throw std::runtime_error("a batch is missing or out of order before " + where() +
                               ": expected seq " + std::to_string(next_seq_));
    any_ = true;
    flight_ = key;
    next_window_ = 1;
    next_seq_ = h.seq + 1;
    return Step::kNext;
  }
  if (h.window < next_window_) return Step::kResend;
  if (h.window != next_window_ || h.seq != next_seq_)
    throw std::runtime_error("a batch is missing before " + where() + ": expected window " +
                             std::to_string(next_window_) + ", seq " + std::to_string(next_seq_));
  ++next_window_;
  ++next_seq_;
  return Step::kNext;
}

void InputForm::expect(Form f, const std::string& channel) {
  if (form_ == Form::kUnknown) form_ = f;
  if (form_ != f)
    throw std::runtime_error(channel + " sends " + (f == Form::kBatches ? "batches" : "single samples") +
                             " but another input sent " + (f == Form::kBatches ? "single samples" : "batches") +
                             ": all inputs must come in the same form");
}

std::string foreign_type_error(const std::string& channel, const char* batch_type, const char* sample_type) {
  return "a message on " + channel + " is neither " + batch_type + " nor " + sample_type +
         " (its type fingerprint matches neither)";
}

std::string free_input_summary(long received, const InputForm& form, long flights, long incomplete, const FreeSkips& skips) {
  std::string s = std::to_string(received) + " message(s) received";
  if (form.form() == InputForm::Form::kBatches)
    s += " as batches: " + std::to_string(flights) + " flight(s), " + std::to_string(incomplete) +
         " of them incomplete, " + std::to_string(skips.resends) + " resent and " + std::to_string(skips.stale) +
         " stale batch(es) skipped";
  else if (form.form() == InputForm::Form::kSamples)
    s += " as single samples";
  return s;
}

bool RecentCopies::seen(const void* data, int size) {
  const std::uint64_t d = message_digest(data, size);
  if (set_.count(d)) return true;
  set_.insert(d);
  order_.push_back(d);
  if (order_.size() > kCapacity) {
    set_.erase(order_.front());
    order_.pop_front();
  }
  return false;
}

}  // namespace rnav
