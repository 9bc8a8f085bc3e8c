#include "estimators/prl_bias/prl_bias_stream.hpp"

namespace rnav {

PrlBiasStream::PrlBiasStream(const PrlBiasOptions& o, const SiteContext& site)
    : wait_us_(to_us(o.nav_wait_s)),
      max_gap_us_(to_us(o.max_nav_gap_s)),
      frame_R_(site.radar_frame()),
      est_(o, site.runner.epoch_utime) {}

void PrlBiasStream::reset() {
  est_.reset();
  nav_.clear();
  pending_.clear();
}

void PrlBiasStream::add_nav(const nav_solution_t& nav) { nav_.add(nav_to_radar_frame(nav, frame_R_)); }

void PrlBiasStream::process_ready(std::int64_t now_utime, std::vector<PrlBiasEstimator::Output>& out) {
  while (!pending_.empty()) {
    const prl_plot_t& plot = pending_.front();
    std::optional<NavAtPlot> nav;
    if (est_.estimating_at(plot.utime)) {
      const auto d = nav_.decide(plot.utime, wait_us_, max_gap_us_, now_utime);
      if (d.decision == NavBuffer::Decision::kWait) return;
      if (d.decision == NavBuffer::Decision::kInterpolate)
        nav = NavAtPlot{hermite_position(*d.before, *d.after, plot.utime), d.after->sigma_pos_m};
    }
    out.push_back(est_.process(plot, nav));
    nav_.prune_before(plot.utime, max_gap_us_);
    pending_.pop_front();
  }
}

}  // namespace rnav
