#include "prl_bias_free_node.hpp"

#include "channels.hpp"

#include <rnav/prl_bias_batch_t.hpp>

#include <algorithm>

namespace rnav {

namespace {
constexpr std::int64_t kEndOfInput = std::numeric_limits<std::int64_t>::max();

}  // namespace

PrlBiasFreeNode::PrlBiasFreeNode(Bus& bus, const Scenario& sc, const PrlBiasFreeOptions& o)
    : bus_(bus), o_(o), stream_(sc), apoi_in_(ch::kApoi, form_, skips_), nav_in_(ch::kNav, form_, skips_) {
  if (!(o.nav_lateness_s >= 0 && o.nav_lateness_s <= 3600))
    throw std::invalid_argument("nav_lateness_s must be in [0, 3600] s");
  bus.subscribe_raw(ch::kApoi, [this](const std::string&, const void* d, int n) { on_apoi(d, n); });
  bus.subscribe_raw(ch::kNav, [this](const std::string&, const void* d, int n) { on_nav(d, n); });
}

void PrlBiasFreeNode::enter_flight(const FlightKey& f) {
  if (f <= flight_) return;
  if (!apoi_q_.empty() || !nav_q_.empty() || stream_.pending() > 0) ++incomplete_flights_;
  apoi_q_.clear();
  nav_q_.clear();
  stream_.reset();
  flight_ = f;
  ++flights_;
}

void PrlBiasFreeNode::on_apoi(const void* data, int size) {
  ++received_;
  apoi_in_.take(
      data, size, flight_,
      queue(apoi_q_),
      [this](const prl_plot_t& p) {
        if (p.utime <= last_plot_utime_)
          throw std::runtime_error(std::string(ch::kApoi) + ": plot " + std::to_string(p.plot_id) + " at utime " +
                                   std::to_string(p.utime) + " does not follow the previous plot's " +
                                   std::to_string(last_plot_utime_) + " (a new flight needs a new estimator)");
        last_plot_utime_ = p.utime;
        stream_.add_plot(p);
        step_samples(std::max(nav_known_, p.utime - to_us(o_.nav_lateness_s)));
      });
}

void PrlBiasFreeNode::on_nav(const void* data, int size) {
  ++received_;
  nav_in_.take(
      data, size, flight_,
      queue(nav_q_),
      [this](const nav_solution_t& n) {
        if (n.link_utime < last_nav_link_)
          throw std::runtime_error(std::string(ch::kNav) + ": a solution reached the ground at " +
                                   std::to_string(n.link_utime) + " us, before the previous one's " +
                                   std::to_string(last_nav_link_) + " (a new flight needs a new estimator)");
        last_nav_link_ = n.link_utime;
        stream_.add_nav(n);
        nav_known_ = std::max(nav_known_, n.link_utime + 1);
        step_samples(nav_known_);
      });
}

void PrlBiasFreeNode::drain_windows() {
  while (!apoi_q_.empty() && !nav_q_.empty()) {
    const prl_plot_batch_t& a = apoi_q_.front();
    const nav_batch_t& n = nav_q_.front();
    if (a.header.window != n.header.window)  // BatchOrder keeps both in window order from 0
      throw std::logic_error("prl_bias --free: PRL_APOI and NAV_SOLUTION windows out of step");
    for (const auto& p : a.plots) stream_.add_plot(p);
    for (const auto& x : n.solutions) stream_.add_nav(x);
    // Every solution that reached the ground before the window's end is in this batch or earlier.
    out_.clear();
    stream_.process_ready(n.header.utime_end, out_);
    prl_bias_batch_t bias;
    prl_plot_batch_t toi;
    bias.header = toi.header = a.header;
    bias.header.seq = bias_seq_++;
    toi.header.seq = toi_seq_++;
    for (const auto& o : out_) {
      bias.estimates.push_back(o.estimate);
      toi.plots.push_back(o.compensated);
    }
    bias.n = static_cast<int>(bias.estimates.size());
    toi.n = static_cast<int>(toi.plots.size());
    bus_.publish(ch::kBias, bias);
    bus_.publish(ch::kToi, toi);
    published_ += toi.n;
    apoi_q_.pop_front();
    nav_q_.pop_front();
  }
}

void PrlBiasFreeNode::step_samples(std::int64_t now_utime) {
  out_.clear();
  stream_.process_ready(now_utime, out_);
  for (const auto& o : out_) {
    bus_.publish(ch::kBias, o.estimate);
    bus_.publish(ch::kToi, o.compensated);
    ++published_;
  }
}

void PrlBiasFreeNode::flush() {
  // Single samples: the feed has ended, every waiting plot is decided with what arrived.
  // Batches: the lock-step run decided everything by its last window; what waits belongs to
  // an incomplete flight (reported).
  if (form_.form() == InputForm::Form::kSamples) step_samples(kEndOfInput);
  else if (!apoi_q_.empty() || !nav_q_.empty() || stream_.pending() > 0) ++incomplete_flights_;
}

std::string PrlBiasFreeNode::summary() const {
  return free_input_summary(received_, form_, flights_, incomplete_flights_, skips_) + "; " + std::to_string(published_) +
         " plot(s) estimated and published";
}

}  // namespace rnav
