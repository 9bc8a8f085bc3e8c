#include "sim/prl/prl_node.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/prl_error_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

namespace rnav {

PrlNode::PrlNode(Bus& bus, const PrlOptions& o, const PrlEffectsOptions& fx, const SiteContext& site)
    : LockstepNode(bus, "prl", site.runner.peer_timeout_s),
      o_(o),
      site_(site),
      frame_L_(site.landing_frame()),
      frame_R_(site.radar_frame()),
      model_(o, fx, site.radar.azimuth_reference_deg) {
  add_input<aircraft_truth_batch_t>(ch::kTruth);
}

void PrlNode::reset(const sim_window_t& w) {
  rng_.emplace(static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization),
               Stream::kPrl);
  model_.start(*rng_);
  plot_id_ = 0;
}

int PrlNode::process(const sim_window_t&) {
  const auto& truth = input<aircraft_truth_batch_t>(ch::kTruth);
  const std::int64_t period = to_us(o_.period_s), phase = to_us(o_.phase_s);
  prl_plot_batch_t plots;
  prl_error_batch_t errors;
  for (const auto& s : truth.states) {
    const std::int64_t t = s.utime - site_.runner.epoch_utime;
    if (t < phase || (t - phase) % period != 0) continue;
    PlotTruth pt;
    pt.t_s = t * 1e-6;
    const Geodetic g{s.lat_deg, s.lon_deg, s.h_m};
    pt.p_RA_R = frame_R_.from_geodetic(g);
    // v_R = R_R_ECEF R_ECEF_L v_L
    pt.v_A_R = frame_R_.R_F_ECEF() * frame_L_.R_F_ECEF().transpose() *
               Eigen::Vector3d(s.v_A_L[0], s.v_A_L[1], s.v_A_L[2]);
    pt.polar = polar_from_cartesian(pt.p_RA_R);
    if (pt.polar.range_m > o_.max_range_m) continue;
    PolarError sys, total;
    model_.apply(pt, *rng_, sys, total);
    prl_plot_t p;
    p.utime = s.utime;
    p.plot_id = plot_id_++;
    p.range_m = pt.polar.range_m + total.range_m;
    p.course_rad = wrap_pi(pt.polar.course_rad + total.course_rad);
    p.glide_rad = pt.polar.glide_rad + total.glide_rad;
    plots.plots.push_back(p);
    prl_error_t e;
    e.utime = s.utime;
    e.plot_id = p.plot_id;
    e.sys_range_m = sys.range_m;
    e.sys_course_rad = sys.course_rad;
    e.sys_glide_rad = sys.glide_rad;
    e.total_range_m = total.range_m;
    e.total_course_rad = total.course_rad;
    e.total_glide_rad = total.glide_rad;
    errors.errors.push_back(e);
  }
  plots.n = static_cast<int>(plots.plots.size());
  errors.n = static_cast<int>(errors.errors.size());
  publish_batch(ch::kApoi, plots);
  publish_batch(ch::kPrlError, errors);
  return plots.n;
}

}  // namespace rnav
