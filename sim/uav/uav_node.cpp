#include "sim/uav/uav_node.hpp"

#include "common/physics/bearing.hpp"
#include <rnav/bearing_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/target_truth_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav {

namespace {
// The orbit centre (straight: the point passed by): the object's first position + offset.
Eigen::Vector2d orbit_centre(const ObserverOptions& uav, const Eigen::Vector2d& target_start_NE_m) {
  return {target_start_NE_m.x() + uav.centre_offset_north_m, target_start_NE_m.y() + uav.centre_offset_east_m};
}
}  // namespace

UavNode::UavNode(Bus& bus, const ObserverOptions& uav, const ObserverNavOptions& nav, const SensorOptions& sensor,
                 const SensorEffectsOptions& effects, const Eigen::Vector2d& target_start_NE_m, const UavContext& ctx)
    : LockstepNode(bus, "uav", ctx.runner.peer_timeout_s),
      uav_(uav),
      nav_(nav),
      sensor_(sensor),
      ctx_(ctx),
      frame_(ctx.frame()),
      path_(uav, orbit_centre(uav, target_start_NE_m), ctx.duration_s),
      corr_{GaussMarkov(nav.corr_sigma_m, nav.corr_tau_s),
            GaussMarkov(nav.corr_sigma_m, nav.corr_tau_s)},
      bearing_error_(sensor, effects),
      limits_(guidance::Limits::from(uav)) {
  add_input<target_truth_batch_t>(ch::kTruthTarget);
  if (closed_loop(uav_)) add_feedback_input<tma_batch_t>(ch::kUavTma);
}

void UavNode::reset(const sim_window_t& w) {
  rng_.emplace(static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization),
               Stream::kUav);
  for (auto& c : corr_) c.start(*rng_);
  bearing_error_.start(*rng_);
  last_t_s_ = 0;
  frame_id_ = 0;
  // Closed loop: start where and as the orbit would (heading making good its course in the wind).
  const ObserverKinematics k0 = path_.at(0.0);
  state_.p_OU_F = k0.p_OU_F;
  state_.heading_rad = guidance::heading_for_course(limits_, k0.course_rad);
  state_t_s_ = 0;
  omega_radps_ = 0;
  last_bearing_rad_.reset();
  estimates_.clear();
}

void UavNode::take_estimates() {
  const auto& b = input<tma_batch_t>(ch::kUavTma);
  bool any_other = false;
  for (const auto& e : b.estimates) {
    if (e.estimator != uav_.guidance_estimator) {
      any_other = true;
      continue;
    }
    if (!estimates_.empty() && e.utime <= estimates_.back().utime)
      throw std::runtime_error("UAV_TMA: estimates of '" + e.estimator + "' not in increasing time (utime " +
                               std::to_string(e.utime) + ")");
    estimates_.push_back({e.utime, Eigen::Vector4d(e.x[0], e.x[1], e.x[2], e.x[3])});
  }
  if (any_other && estimates_.empty())
    throw std::runtime_error("UAV_TMA carries no estimate of uav.guidance_estimator = '" + uav_.guidance_estimator +
                             "' (is that estimator running?)");
}

const UavNode::HeldEstimate* UavNode::estimate_at(std::int64_t utime) const {
  auto it = std::upper_bound(estimates_.begin(), estimates_.end(), utime,
                             [](std::int64_t u, const HeldEstimate& e) { return u < e.utime; });
  return it == estimates_.begin() ? nullptr : &*std::prev(it);
}

ObserverKinematics UavNode::closed_loop_kinematics() const {
  ObserverKinematics k;
  k.p_OU_F = state_.p_OU_F;
  k.v_U_F = guidance::ground_velocity(limits_, state_.heading_rad);
  k.course_rad = std::atan2(k.v_U_F.y(), k.v_U_F.x());
  return k;
}

void UavNode::steer(std::int64_t utime, const Eigen::Vector2d& p_nav_F, const bearing_t* measured) {
  if (measured) last_bearing_rad_ = measured->bearing_rad;
  // The estimate estimate_latency_s old, predicted to now with its velocity: p = p_e + v_e (t - t_e).
  const HeldEstimate* e = estimate_at(utime - static_cast<std::int64_t>(std::llround(uav_.estimate_latency_s * 1e6)));
  std::optional<Eigen::Vector2d> d;  // line of sight from the UAV (its nav solution) to the estimate
  if (e) d = e->x.head<2>() + e->x.tail<2>() * ((utime - e->utime) * 1e-6) - p_nav_F;
  std::optional<double> beta, range;
  if (d) range = d->norm();
  if (uav_.guidance == "estimate" && d) {
    beta = bearing_rad(*d);
  } else if (last_bearing_rad_) {
    beta = *last_bearing_rad_;  // los, or no estimate yet: the measured bearing
  }
  // No bearing ever (object not yet in the field of regard): hold the heading, turning at the orbit's rate.
  const double psi_d = beta ? guidance::heading_for_course(limits_, guidance::desired_course(limits_, *beta, range))
                            : state_.heading_rad;
  omega_radps_ = guidance::turn_rate_command(limits_, state_.heading_rad, psi_d);
}

int UavNode::process(const sim_window_t&) {
  const auto& truth = input<target_truth_batch_t>(ch::kTruthTarget);
  if (closed_loop(uav_)) take_estimates();
  observer_batch_t true_uav, nav;
  bearing_batch_t bearings;
  const double sigma_b = sensor_.sigma_deg * kDegToRad;  // the sensor's stated accuracy
  const double white = nav_.white_sigma_m;
  const double sigma_nav = std::sqrt(white * white + nav_.corr_sigma_m * nav_.corr_sigma_m);
  for (const auto& ts : truth.states) {
    const double t = (ts.utime - ctx_.runner.epoch_utime) * 1e-6;
    if (closed_loop(uav_) && t > state_t_s_) {
      state_ = guidance::propagate(limits_, state_, omega_radps_, t - state_t_s_);
      state_t_s_ = t;
    }
    const ObserverKinematics k = closed_loop(uav_) ? closed_loop_kinematics() : path_.at(t);
    auto fill = [&](observer_state_t& o, const Eigen::Vector2d& p, const Eigen::Vector2d& v, double sig) {
      o.utime = ts.utime;
      o.p_OU_F[0] = p.x();
      o.p_OU_F[1] = uav_.altitude_m;
      o.p_OU_F[2] = p.y();
      o.v_U_F[0] = v.x();
      o.v_U_F[1] = 0;
      o.v_U_F[2] = v.y();
      const Geodetic g = frame_.to_geodetic(Eigen::Vector3d(p.x(), uav_.altitude_m, p.y()));
      o.lat_deg = g.lat_deg;
      o.lon_deg = g.lon_deg;
      o.h_m = g.h_m;
      o.sigma_pos_m = sig;
    };
    observer_state_t tru, sol;
    fill(tru, k.p_OU_F, k.v_U_F, 0.0);
    true_uav.states.push_back(tru);
    // Navigation error: Gauss-Markov + white per horizontal axis (draw order fixed).
    const double dt = t - last_t_s_;
    last_t_s_ = t;
    Eigen::Vector2d dp, dv;
    for (int i = 0; i < 2; ++i) {
      dp[i] = corr_[i].step(dt, *rng_) + white * rng_->normal();
      dv[i] = nav_.vel_sigma_mps * rng_->normal();
    }
    fill(sol, k.p_OU_F + dp, k.v_U_F + dv, sigma_nav);
    nav.states.push_back(sol);
    // Sensor: the true bearing from the true UAV position, within the field of regard.
    const Eigen::Vector2d d(ts.p_OT_F[0] - k.p_OU_F.x(), ts.p_OT_F[1] - k.p_OU_F.y());
    const double truth_b = bearing_rad(d);
    const double rel = wrap_pi(truth_b - k.course_rad - sensor_.fov_centre_deg * kDegToRad);
    BearingTruth bt;
    bt.t_s = t;
    bt.bearing_rad = truth_b;
    bt.range_m = d.norm();
    // d(bearing)/dt = (d x v_rel) / |d|^2 with v_rel = v_T - v_U (2-D cross product, north-east)
    const Eigen::Vector2d vrel(ts.v_T_F[0] - k.v_U_F.x(), ts.v_T_F[1] - k.v_U_F.y());
    bt.bearing_rate_radps = (d.x() * vrel.y() - d.y() * vrel.x()) / d.squaredNorm();
    const double noise = bearing_error_.error(bt, *rng_);  // every frame: gaps do not shift the stream
    const std::int64_t fid = frame_id_++;
    const bool detected = std::abs(rel) <= sensor_.fov_half_deg * kDegToRad && d.norm() <= sensor_.max_range_m &&
                          d.norm() >= sensor_.min_range_m;
    if (detected) {
      bearing_t b;
      b.utime = ts.utime;
      b.frame_id = fid;
      b.bearing_rad = wrap_pi(truth_b + noise);
      b.sigma_rad = sigma_b;
      bearings.bearings.push_back(b);
    }
    if (closed_loop(uav_))
      steer(ts.utime, Eigen::Vector2d(sol.p_OU_F[0], sol.p_OU_F[2]), detected ? &bearings.bearings.back() : nullptr);
  }
  true_uav.n = static_cast<int>(true_uav.states.size());
  nav.n = static_cast<int>(nav.states.size());
  bearings.n = static_cast<int>(bearings.bearings.size());
  publish_batch(ch::kTruthUav, true_uav);
  publish_batch(ch::kUavNav, nav);
  publish_batch(ch::kUavBearing, bearings);
  return bearings.n;
}

}  // namespace rnav
