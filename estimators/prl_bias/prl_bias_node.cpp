#include "prl_bias_node.hpp"

#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

namespace rnav {

PrlBiasNode::PrlBiasNode(Bus& bus, const Scenario& sc)
    : LockstepNode(bus, "prl_bias", sc.runner.peer_timeout_s),
      sc_(sc),
      frame_R_(sc.radar_frame()),
      est_(sc.prl_bias, sc.runner.epoch_utime) {
  add_input<prl_plot_batch_t>(ch::kApoi);
  add_input<nav_batch_t>(ch::kNav);
}

void PrlBiasNode::reset(const sim_window_t&) {
  est_.reset();
  nav_.clear();
  pending_.clear();
}

int PrlBiasNode::process(const sim_window_t& w) {
  for (const auto& p : input<prl_plot_batch_t>(ch::kApoi).plots) pending_.push_back(p);
  for (const auto& n : input<nav_batch_t>(ch::kNav).solutions)
    nav_.add(nav_to_radar_frame(n, frame_R_));

  const std::int64_t wait = to_us(sc_.prl_bias.nav_wait_s), gap = to_us(sc_.prl_bias.max_nav_gap_s);
  prl_bias_batch_t bias;
  prl_plot_batch_t toi;
  while (!pending_.empty()) {
    const prl_plot_t& plot = pending_.front();
    std::optional<NavAtPlot> nav;
    if (est_.estimating_at(plot.utime)) {
      const auto d = nav_.decide(plot.utime, wait, gap, w.utime_end);
      if (d.decision == NavBuffer::Decision::kWait) {
        if (w.last_window)
          throw std::runtime_error("plot " + std::to_string(plot.plot_id) +
                                   " undecided at the end of the realization (runner.flush_s too short)");
        break;
      }
      if (d.decision == NavBuffer::Decision::kInterpolate)
        nav = NavAtPlot{hermite_position(*d.before, *d.after, plot.utime), d.after->sigma_pos_m};
    }
    const auto out = est_.process(plot, nav);
    bias.estimates.push_back(out.estimate);
    toi.plots.push_back(out.compensated);
    nav_.prune_before(plot.utime, gap);
    pending_.pop_front();
  }
  bias.n = static_cast<int>(bias.estimates.size());
  toi.n = static_cast<int>(toi.plots.size());
  publish_batch(ch::kBias, bias);
  publish_batch(ch::kToi, toi);
  return toi.n;
}

}  // namespace rnav
