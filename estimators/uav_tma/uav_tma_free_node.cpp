#include "uav_tma_free_node.hpp"

#include "channels.hpp"

#include <rnav/tma_batch_t.hpp>

namespace rnav {

UavTmaFreeNode::UavTmaFreeNode(Bus& bus, const UavScenario& sc, const UavTmaFreeOptions& o)
    : bus_(bus), sc_(sc), o_(o), est_(tma::make_estimators(sc.tma, static_cast<std::uint64_t>(o.seed), 0)),
      nav_in_(ch::kUavNav, form_, skips_), bearing_in_(ch::kUavBearing, form_, skips_) {
  if (!(o.bearing_lateness_s >= 0 && o.bearing_lateness_s <= 3600))
    throw std::invalid_argument("bearing_lateness_s must be in [0, 3600] s");
  bus.subscribe_raw(ch::kUavNav, [this](const std::string&, const void* d, int n) { on_nav(d, n); });
  bus.subscribe_raw(ch::kUavBearing, [this](const std::string&, const void* d, int n) { on_bearing(d, n); });
}

void UavTmaFreeNode::enter_flight(const FlightKey& f) {
  if (f <= flight_) return;
  if (!nav_q_.empty() || !bearing_q_.empty()) ++incomplete_flights_;
  nav_q_.clear();
  bearing_q_.clear();
  est_ = tma::make_estimators(sc_.tma, static_cast<std::uint64_t>(o_.seed), static_cast<std::uint64_t>(f.first));
  flight_ = f;
  ++flights_;
}

void UavTmaFreeNode::on_nav(const void* data, int size) {
  ++received_;
  nav_in_.take(
      data, size, flight_,
      queue(nav_q_),
      [this](const observer_state_t& o) {
        if (o.utime <= last_nav_utime_)
          throw std::runtime_error(std::string(ch::kUavNav) + ": a state at utime " + std::to_string(o.utime) +
                                   " does not follow the previous one's " + std::to_string(last_nav_utime_) +
                                   " (a new flight needs a new estimator)");
        last_nav_utime_ = o.utime;
        frames_.push_back(o);
        step_samples(false);
      });
}

void UavTmaFreeNode::on_bearing(const void* data, int size) {
  ++received_;
  bearing_in_.take(
      data, size, flight_,
      queue(bearing_q_),
      [this](const bearing_t& b) {
        if (b.utime < last_bearing_utime_)
          throw std::runtime_error(std::string(ch::kUavBearing) + ": a bearing at utime " + std::to_string(b.utime) +
                                   " does not follow the previous one's " + std::to_string(last_bearing_utime_) +
                                   " (a new flight needs a new estimator)");
        last_bearing_utime_ = b.utime;
        bearings_.emplace(b.utime, b);
        step_samples(false);
      });
}

void UavTmaFreeNode::drain_windows() {
  while (!nav_q_.empty() && !bearing_q_.empty()) {
    const observer_batch_t& n = nav_q_.front();
    const bearing_batch_t& b = bearing_q_.front();
    if (n.header.window != b.header.window)  // BatchOrder keeps both in window order from 0
      throw std::logic_error("uav_tma --free: UAV_NAV and UAV_BEARING windows out of step");
    tma_batch_t out;
    out.header = n.header;
    out.header.seq = seq_++;
    tma_window(est_, sc_.runner.epoch_utime, n, b, out.estimates);
    out.n = static_cast<int>(out.estimates.size());
    bus_.publish(ch::kUavTma, out);
    frames_done_ += n.n;
    nav_q_.pop_front();
    bearing_q_.pop_front();
  }
}

void UavTmaFreeNode::step_samples(bool end_of_input) {
  const std::int64_t lateness_us = to_us(o_.bearing_lateness_s);
  std::vector<const bearing_t*> frame;
  while (!frames_.empty()) {
    const observer_state_t& o = frames_.front();
    // Are all bearings at o.utime in? (bearings arrive in time order)
    const bool ready = end_of_input || last_bearing_utime_ > o.utime ||
                       (last_nav_utime_ != std::numeric_limits<std::int64_t>::min() &&
                        last_nav_utime_ - o.utime >= lateness_us);
    if (!ready) return;
    if (!bearings_.empty() && bearings_.begin()->first < o.utime)
      throw std::runtime_error(std::string(ch::kUavBearing) + " at utime " + std::to_string(bearings_.begin()->first) +
                               " has no UAV_NAV state at its time");
    frame.clear();
    const auto range = bearings_.equal_range(o.utime);
    for (auto it = range.first; it != range.second; ++it) frame.push_back(&it->second);
    out_.clear();
    process_tma_frame(est_, sc_.runner.epoch_utime, o, frame, out_);
    for (const auto& m : out_) bus_.publish(ch::kUavTma, m);
    bearings_.erase(range.first, range.second);
    frames_.pop_front();
    ++frames_done_;
  }
  if (end_of_input && !bearings_.empty())
    throw std::runtime_error(std::string(ch::kUavBearing) + " at utime " + std::to_string(bearings_.begin()->first) +
                             " has no UAV_NAV state at its time");
}

void UavTmaFreeNode::flush() {
  if (form_.form() == InputForm::Form::kSamples) step_samples(true);
  else if (!nav_q_.empty() || !bearing_q_.empty()) ++incomplete_flights_;
}

std::string UavTmaFreeNode::summary() const {
  return free_input_summary(received_, form_, flights_, incomplete_flights_, skips_) + "; " +
         std::to_string(frames_done_) + " frame(s) processed";
}

}  // namespace rnav
