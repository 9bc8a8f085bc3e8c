#include "scripts/compose/export/prl_csv_recorder_node.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

namespace rnav {

PrlCsvRecorderNode::PrlCsvRecorderNode(Bus& bus, const Scenario& sc, int realization,
                                       std::string out_dir)
    : LockstepNode(bus, "recorder", sc.runner.peer_timeout_s),
      sc_(sc),
      realization_(realization),
      out_dir_(std::move(out_dir)) {
  add_input<aircraft_truth_batch_t>(ch::kTruth);
  add_input<prl_plot_batch_t>(ch::kApoi);
  add_input<nav_batch_t>(ch::kNav);
}

void PrlCsvRecorderNode::reset(const sim_window_t& w) {
  recording_ = w.realization == realization_;
  if (!recording_) return;  // keep what was recorded
  data_ = PrlFlightData{};
  data_.radar_site = sc_.radar_site();
  data_.azimuth_reference_deg = sc_.radar.azimuth_reference_deg;
  data_.threshold = sc_.runway.threshold;
  data_.heading_deg = sc_.runway.heading_deg;
}

int PrlCsvRecorderNode::process(const sim_window_t&) {
  if (!recording_) return 0;
  auto t_of = [&](std::int64_t u) { return (u - sc_.runner.epoch_utime) * 1e-6; };
  for (const auto& s : input<aircraft_truth_batch_t>(ch::kTruth).states)
    data_.truth.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
  for (const auto& p : input<prl_plot_batch_t>(ch::kApoi).plots) {
    data_.t_s.push_back(t_of(p.utime));
    data_.plots.push_back({p.range_m, p.course_rad, p.glide_rad});
  }
  for (const auto& n : input<nav_batch_t>(ch::kNav).solutions)
    data_.nav.push_back({t_of(n.utime), {n.lat_deg, n.lon_deg, n.h_m}});
  return 0;
}

void PrlCsvRecorderNode::finish(const sim_window_t&) {
  if (data_.plots.empty()) throw std::runtime_error("recorder: realization " + std::to_string(realization_) + " was not run");
  data_.write_folder(out_dir_);
}

}  // namespace rnav
