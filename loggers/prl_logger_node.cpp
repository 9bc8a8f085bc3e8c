#include "loggers/prl_logger_node.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_error_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

namespace rnav {

PrlLoggerNode::PrlLoggerNode(Bus& bus, const LoggerOptions& o, const SiteContext& site, std::string scenario_json,
                             std::string out_dir)
    : EnsembleLoggerNode(bus, "logger", site.runner.peer_timeout_s, PrlStats(o, site), std::move(scenario_json),
                         std::move(out_dir)),
      o_(o),
      T_L_R_(transform(site.landing_frame(), site.radar_frame())) {
  add_input<aircraft_truth_batch_t>(ch::kTruth);
  add_input<prl_plot_batch_t>(ch::kApoi);
  add_input<prl_error_batch_t>(ch::kPrlError);
  add_input<prl_plot_batch_t>(ch::kToi);
  add_input<prl_bias_batch_t>(ch::kBias);
}

void PrlLoggerNode::start_realization(const sim_window_t& /*w*/) {
  truth_.clear();
  apoi_.clear();
  toi_.clear();
  err_.clear();
  bias_.clear();
}

int PrlLoggerNode::process(const sim_window_t& w) {
  for (const auto& s : input<aircraft_truth_batch_t>(ch::kTruth).states)
    truth_[s.utime] = Eigen::Vector3d(s.p_TA_L[0], s.p_TA_L[1], s.p_TA_L[2]);
  for (const auto& p : input<prl_plot_batch_t>(ch::kApoi).plots) apoi_[p.plot_id] = p;
  for (const auto& e : input<prl_error_batch_t>(ch::kPrlError).errors) err_[e.plot_id] = e;
  for (const auto& p : input<prl_plot_batch_t>(ch::kToi).plots) toi_[p.plot_id] = p;
  for (const auto& b : input<prl_bias_batch_t>(ch::kBias).estimates) bias_[b.plot_id] = b;

  // Join complete plots in plot order.
  while (!apoi_.empty()) {
    const auto id = apoi_.begin()->first;
    if (!toi_.count(id) || !bias_.count(id) || !err_.count(id)) break;
    const prl_plot_t& raw = apoi_.begin()->second;
    const auto tr = truth_.find(raw.utime);
    if (tr == truth_.end())
      throw std::runtime_error("no TRUTH_AIRCRAFT state at the time of plot " + std::to_string(id));
    const prl_plot_t& comp = toi_.at(id);
    const prl_error_t& e = err_.at(id);
    const prl_bias_estimate_t& b = bias_.at(id);
    if (comp.utime != raw.utime || b.utime != raw.utime || e.utime != raw.utime)
      throw std::runtime_error("plot " + std::to_string(id) + ": time stamps disagree between streams");
    PlotErrors pe;
    pe.utime = raw.utime;
    const Eigen::Vector3d p_true = tr->second;
    // e_L = p_plot_L - p_true_L with p_plot_L = T_L_R * cartesian(D, Ek, Eg)
    const Eigen::Vector3d ea =
        T_L_R_ * cartesian_from_polar({raw.range_m, raw.course_rad, raw.glide_rad}) - p_true;
    const Eigen::Vector3d et =
        T_L_R_ * cartesian_from_polar({comp.range_m, comp.course_rad, comp.glide_rad}) - p_true;
    pe.apoi = {ea.x(), ea.z(), ea.y()};
    pe.toi = {et.x(), et.z(), et.y()};
    pe.p_true_L = {p_true.x(), p_true.y(), p_true.z()};
    pe.range_true_m = (T_L_R_.inverse() * p_true).norm();
    pe.range_table_m = o_.table_range_origin == "radar" ? pe.range_true_m : p_true.norm();
    pe.bias_err = {b.eta[0] - e.sys_range_m, b.eta[1] - e.sys_course_rad, b.eta[2] - e.sys_glide_rad};
    pe.bias_var = {b.var[0], b.var[1], b.var[2]};
    pe.mode = b.mode;
    current_.push_back(pe);
    apoi_.erase(apoi_.begin());
    toi_.erase(id);
    err_.erase(id);
    bias_.erase(id);
  }
  // Truth before the oldest unjoined plot is no longer needed.
  const std::int64_t keep_from = apoi_.empty() ? w.utime_end : apoi_.begin()->second.utime;
  truth_.erase(truth_.begin(), truth_.lower_bound(keep_from));

  if (w.last_window && (!apoi_.empty() || !toi_.empty() || !bias_.empty() || !err_.empty()))
    throw std::runtime_error(
        "realization " + std::to_string(w.realization) + " ended with unmatched plots: " +
        std::to_string(apoi_.size()) + " raw without estimator output, " + std::to_string(toi_.size()) +
        " compensated, " + std::to_string(bias_.size()) + " estimates, " +
        std::to_string(err_.size()) + " error records left over");
  return static_cast<int>(current_.size());
}

}  // namespace rnav
