#include "estimators/prl_bias/prl_bias_free_node.hpp"

#include "common/node/channels.hpp"

#include <rnav/prl_bias_batch_t.hpp>

#include <algorithm>

namespace rnav {

namespace {
constexpr std::int64_t kEndOfInput = std::numeric_limits<std::int64_t>::max();

}  // namespace

PrlBiasFreeNode::PrlBiasFreeNode(Bus& bus, const PrlBiasOptions& bias, const SiteContext& site, const PrlBiasFreeOptions& o)
    : PairedFreeNode(bus, "prl_bias", ch::kApoi, ch::kNav), o_(o), stream_(bias, site),
      plot_times_(ch::kApoi, ForwardTimes::Ties::kRefused), nav_links_(ch::kNav, ForwardTimes::Ties::kAllowed) {
  if (!(o.nav_lateness_s >= 0 && o.nav_lateness_s <= 3600))
    throw std::invalid_argument("nav_lateness_s must be in [0, 3600] s");
  listen();
}

void PrlBiasFreeNode::on_new_flight(const FlightKey&) { stream_.reset(); }

void PrlBiasFreeNode::on_sample_a(const prl_plot_t& p) {
  plot_times_.take(p.utime, [&](std::int64_t last) {
    return "plot " + std::to_string(p.plot_id) + " at utime " + std::to_string(p.utime) +
           " does not follow the previous plot's " + std::to_string(last);
  });
  stream_.add_plot(p);
  step_samples(std::max(nav_known_, p.utime - to_us(o_.nav_lateness_s)));
}

void PrlBiasFreeNode::on_sample_b(const nav_solution_t& n) {
  nav_links_.take(n.link_utime, [&](std::int64_t last) {
    return "a solution reached the ground at " + std::to_string(n.link_utime) + " us, before the previous one's " +
           std::to_string(last);
  });
  stream_.add_nav(n);
  nav_known_ = std::max(nav_known_, n.link_utime + 1);
  step_samples(nav_known_);
}

void PrlBiasFreeNode::on_window(const prl_plot_batch_t& a, const nav_batch_t& n) {
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
  bus().publish(ch::kBias, bias);
  bus().publish(ch::kToi, toi);
  published_ += toi.n;
}

void PrlBiasFreeNode::step_samples(std::int64_t now_utime) {
  out_.clear();
  stream_.process_ready(now_utime, out_);
  for (const auto& o : out_) {
    bus().publish(ch::kBias, o.estimate);
    bus().publish(ch::kToi, o.compensated);
    ++published_;
  }
}

// The feed has ended: every waiting plot is decided with what arrived.
void PrlBiasFreeNode::on_end_of_samples() { step_samples(kEndOfInput); }

std::string PrlBiasFreeNode::output_summary() const {
  return std::to_string(published_) + " plot(s) estimated and published";
}

}  // namespace rnav
