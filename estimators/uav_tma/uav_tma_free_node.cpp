#include "estimators/uav_tma/uav_tma_free_node.hpp"

#include "common/node/channels.hpp"

#include <rnav/tma_batch_t.hpp>

namespace rnav {

UavTmaFreeNode::UavTmaFreeNode(Bus& bus, const TmaOptions& tma, const UavContext& ctx, const UavTmaFreeOptions& o)
    : PairedFreeNode(bus, "uav_tma", ch::kUavNav, ch::kUavBearing), tma_(tma), ctx_(ctx), o_(o),
      est_(tma::make_estimators(tma, static_cast<std::uint64_t>(o.seed), 0)),
      nav_times_(ch::kUavNav, ForwardTimes::Ties::kRefused),
      bearing_times_(ch::kUavBearing, ForwardTimes::Ties::kAllowed) {
  if (!(o.bearing_lateness_s >= 0 && o.bearing_lateness_s <= 3600))
    throw std::invalid_argument("bearing_lateness_s must be in [0, 3600] s");
  listen();
}

void UavTmaFreeNode::on_new_flight(const FlightKey& f) {
  est_ = tma::make_estimators(tma_, static_cast<std::uint64_t>(o_.seed), static_cast<std::uint64_t>(f.first));
}

void UavTmaFreeNode::on_sample_a(const observer_state_t& o) {
  nav_times_.take(o.utime, [&](std::int64_t last) {
    return "a state at utime " + std::to_string(o.utime) + " does not follow the previous one's " +
           std::to_string(last);
  });
  frames_.push_back(o);
  step_samples(false);
}

void UavTmaFreeNode::on_sample_b(const bearing_t& b) {
  bearing_times_.take(b.utime, [&](std::int64_t last) {
    return "a bearing at utime " + std::to_string(b.utime) + " does not follow the previous one's " +
           std::to_string(last);
  });
  bearings_.emplace(b.utime, b);
  step_samples(false);
}

void UavTmaFreeNode::on_window(const observer_batch_t& n, const bearing_batch_t& b) {
  tma_batch_t out;
  out.header = n.header;
  out.header.seq = seq_++;
  tma_window(est_, ctx_.runner.epoch_utime, n, b, out.estimates);
  out.n = static_cast<int>(out.estimates.size());
  bus().publish(ch::kUavTma, out);
  frames_done_ += n.n;
}

void UavTmaFreeNode::step_samples(bool end_of_input) {
  const std::int64_t lateness_us = to_us(o_.bearing_lateness_s);
  std::vector<const bearing_t*> frame;
  while (!frames_.empty()) {
    const observer_state_t& o = frames_.front();
    // Are all bearings at o.utime in? (bearings arrive in time order)
    const bool ready = end_of_input || bearing_times_.last() > o.utime ||
                       (nav_times_.any() && nav_times_.last() - o.utime >= lateness_us);
    if (!ready) return;
    if (!bearings_.empty() && bearings_.begin()->first < o.utime)
      throw std::runtime_error(std::string(ch::kUavBearing) + " at utime " + std::to_string(bearings_.begin()->first) +
                               " has no UAV_NAV state at its time");
    frame.clear();
    const auto range = bearings_.equal_range(o.utime);
    for (auto it = range.first; it != range.second; ++it) frame.push_back(&it->second);
    out_.clear();
    process_tma_frame(est_, ctx_.runner.epoch_utime, o, frame, out_);
    for (const auto& m : out_) bus().publish(ch::kUavTma, m);
    bearings_.erase(range.first, range.second);
    frames_.pop_front();
    ++frames_done_;
  }
  if (end_of_input && !bearings_.empty())
    throw std::runtime_error(std::string(ch::kUavBearing) + " at utime " + std::to_string(bearings_.begin()->first) +
                             " has no UAV_NAV state at its time");
}

std::string UavTmaFreeNode::output_summary() const { return std::to_string(frames_done_) + " frame(s) processed"; }

}  // namespace rnav
