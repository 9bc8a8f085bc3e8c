#include "loggers/uav_logger_node.hpp"

#include "common/io/atomic_file.hpp"
#include "estimators/uav_tma/tma_models.hpp"
#include "loggers/uav_realizations.hpp"

#include <rnav/bearing_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/target_truth_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <cmath>
#include <filesystem>

namespace rnav {

UavLoggerNode::UavLoggerNode(Bus& bus, const UavStatsSetup& sc, std::string scenario_json, std::string out_dir)
    : EnsembleLoggerNode(bus, "uav_logger", sc.runner.peer_timeout_s, UavStats(sc), std::move(scenario_json),
                         std::move(out_dir)),
      sc_(sc) {
  add_input<target_truth_batch_t>(ch::kTruthTarget);
  add_input<observer_batch_t>(ch::kTruthUav);
  add_input<bearing_batch_t>(ch::kUavBearing);
  add_input<tma_batch_t>(ch::kUavTma);
}

void UavLoggerNode::start_realization(const sim_window_t& w) {
  tracking_ = !out_dir_.empty() && w.realization == sc_.logger.track_realization;
  track_.clear();  // also what a failed attempt of the tracked realization left
}

int UavLoggerNode::process(const sim_window_t& /*w*/) {
  // Everything of one frame arrives in the same window (all are produced per frame).
  std::map<std::int64_t, tma::Vec4> truth;
  for (const auto& s : input<target_truth_batch_t>(ch::kTruthTarget).states)
    truth[s.utime] = tma::Vec4(s.p_OT_F[0], s.p_OT_F[1], s.v_T_F[0], s.v_T_F[1]);
  std::map<std::int64_t, Eigen::Vector2d> uav;
  for (const auto& o : input<observer_batch_t>(ch::kTruthUav).states)
    uav[o.utime] = Eigen::Vector2d(o.p_OU_F[0], o.p_OU_F[2]);
  for (const auto& [utime, p_U] : uav)
    if (const auto t = truth.find(utime); t != truth.end()) current_.add_range((t->second.head<2>() - p_U).norm());
  if (tracking_) {
    for (const auto& [t, x] : truth) track_.add_object(t, x);
    for (const auto& [t, p] : uav) track_.add_uav(t, p);
    for (const auto& b : input<bearing_batch_t>(ch::kUavBearing).bearings) track_.add_bearing(b.utime, b.bearing_rad);
  }
  const double sb = sc_.sensor.sigma_deg * kDegToRad;
  const double sn = std::hypot(sc_.uav_nav.white_sigma_m, sc_.uav_nav.corr_sigma_m);
  for (const auto& b : input<bearing_batch_t>(ch::kUavBearing).bearings) {
    const auto t = truth.find(b.utime);
    const auto u = uav.find(b.utime);
    if (t == truth.end() || u == uav.end())
      throw std::runtime_error("UAV_BEARING at utime " + std::to_string(b.utime) + " has no truth");
    // Fisher information of this bearing at the truth, with the noise the estimators assume.
    const double D = tma::range(t->second, u->second);
    const double R = sc_.tma.add_nav_noise ? tma::bearing_variance(sb, sn, D) : sb * sb;
    if (current_.first_utime < 0) {
      // The estimators' prior, exactly as they build it: bearing variance at the prior range.
      const double R0 = sc_.tma.add_nav_noise ? tma::bearing_variance(sb, sn, sc_.tma.range_prior_m) : sb * sb;
      current_.first_utime = b.utime;
      current_.J0 = tma::prior_information(tma::bearing(t->second, u->second), sc_.tma.range_prior_m,
                                       sc_.tma.range_sigma_m, R0, sc_.tma.vel_sigma_mps);
    }
    const tma::Row4 H = tma::bearing_jacobian(t->second, u->second);
    auto it = current_.info.find(b.utime);
    const tma::Mat4 I = H.transpose() * H / R;
    if (it == current_.info.end()) current_.info.emplace(b.utime, I);
    else it->second += I;
  }
  int n = 0;
  for (const auto& m : input<tma_batch_t>(ch::kUavTma).estimates) {
    const auto t = truth.find(m.utime);
    if (t == truth.end())
      throw std::runtime_error("UAV_TMA estimate at utime " + std::to_string(m.utime) + " has no truth");
    tma::Vec4 x;
    tma::Mat4 P;
    for (int i = 0; i < 4; ++i) {
      x[i] = m.x[i];
      for (int j = 0; j < 4; ++j) P(i, j) = m.P[i][j];
    }
    if (tracking_) track_.add_estimate(m.utime, m.estimator, x, P);
    const tma::Vec4 e = x - t->second;
    TmaSample s;
    s.utime = m.utime;
    s.estimator = m.estimator;
    s.pos_err2 = e.head<2>().squaredNorm();
    s.vel_err2 = e.tail<2>().squaredNorm();
    s.nees = e.dot(P.ldlt().solve(e));
    for (int i = 0; i < 4; ++i) {
      s.err[i] = e[i];
      s.sigma[i] = std::sqrt(P(i, i));
    }
    s.updated = m.updated;
    s.nis = m.nis;
    current_.samples.push_back(s);
    ++n;
  }
  return n;
}

// The statistics validated the realization first: a rejected one writes no rows.
void UavLoggerNode::committed() {
  if (!out_dir_.empty()) {
    if (!rows_) {
      std::filesystem::create_directories(out_dir_);  // as the results at FINISH (a caller may not have made it)
      rows_ = std::make_unique<AtomicFileWriter>(out_dir_, "realizations.csv");
      rows_->append(csv_header(uav_realizations_columns()));
    }
    rows_->append(uav_realization_rows(sc_, realization_, current_));
    if (tracking_) {
      track_csv_ = track_.csv(sc_.runner.epoch_utime, realization_);
      track_columns_ = UavTrack::columns(track_.estimators());
    }
  }
  track_.clear();
}

void UavLoggerNode::write_own(const sim_window_t& w) {
  if (rows_) {
    rows_->commit();
    write_csv_units(out_dir_, "realizations.csv", uav_realizations_columns());
  }
  // This run holds realizations first ... w.realization (the last one run; FINISH carries it).
  const long first = static_cast<long>(w.realization) - w.n_realizations + 1;
  if (sc_.logger.track_realization >= first && sc_.logger.track_realization <= w.realization) {
    if (track_csv_.empty())
      throw std::runtime_error("track.csv: realization " + std::to_string(sc_.logger.track_realization) +
                               " (logger.track_realization) was never committed");
    write_file_atomic(out_dir_, "track.csv", track_csv_);
    write_csv_units(out_dir_, "track.csv", track_columns_);
  }
}

}  // namespace rnav
