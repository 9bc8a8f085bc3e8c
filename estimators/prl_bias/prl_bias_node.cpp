#include "estimators/prl_bias/prl_bias_node.hpp"

#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

namespace rnav {

PrlBiasNode::PrlBiasNode(Bus& bus, const PrlBiasOptions& o, const SiteContext& site)
    : LockstepNode(bus, "prl_bias", site.runner.peer_timeout_s), stream_(o, site) {
  add_input<prl_plot_batch_t>(ch::kApoi);
  add_input<nav_batch_t>(ch::kNav);
}

void PrlBiasNode::reset(const sim_window_t&) { stream_.reset(); }

int PrlBiasNode::process(const sim_window_t& w) {
  for (const auto& p : input<prl_plot_batch_t>(ch::kApoi).plots) stream_.add_plot(p);
  for (const auto& n : input<nav_batch_t>(ch::kNav).solutions) stream_.add_nav(n);
  // Every solution that reached the ground before the window's end is in this or an earlier batch.
  out_.clear();
  stream_.process_ready(w.utime_end, out_);
  if (w.last_window && stream_.pending() > 0)
    throw std::runtime_error("plot " + std::to_string(stream_.first_pending().plot_id) +
                             " undecided at the end of the realization (runner.flush_s too short)");
  prl_bias_batch_t bias;
  prl_plot_batch_t toi;
  for (const auto& o : out_) {
    bias.estimates.push_back(o.estimate);
    toi.plots.push_back(o.compensated);
  }
  bias.n = static_cast<int>(bias.estimates.size());
  toi.n = static_cast<int>(toi.plots.size());
  publish_batch(ch::kBias, bias);
  publish_batch(ch::kToi, toi);
  return toi.n;
}

}  // namespace rnav
