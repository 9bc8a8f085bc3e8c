#include "estimators/diagnosis/uav_diagnose.hpp"

#include "common/physics/bearing.hpp"
#include "common/physics/bearing_effect_columns.hpp"
#include "common/io/config.hpp"
#include "estimators/diagnosis/bearing_reference_check.hpp"
#include "estimators/diagnosis/gross_check.hpp"
#include "estimators/diagnosis/plane_series.hpp"
#include "estimators/model_id/stats.hpp"
#include "estimators/diagnosis/target_model.hpp"
#include "estimators/diagnosis/uav_track_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace rnav {

namespace {

// One frame's associated detection with the reference geometry.
struct Ob {
  double t = 0;
  double r = 0;      ///< [rad] residual against the reference track
  double rate = 0;   ///< [rad/s] reference bearing rate
  double range = 0;  ///< [m] reference horizontal range
  Eigen::Vector4d J = Eigen::Vector4d::Zero();  ///< estimated reference: d bearing / d (p0, v)
  std::size_t k = 0; ///< estimated reference: index into the track observations
  bearing_effect::FrameGeometry geometry() const { return {t, rate}; }
};
using Obs = std::shared_ptr<const std::vector<Ob>>;

double ramp(double t, double t_m) { return t > t_m ? t - t_m : 0.0; }

// Frames whose nearest detection lies beyond the association gate but within this many gates
// are kept as observations: under the nominal model they are gross errors, which the noise
// identification flags as outliers (and the outlier test judges); beyond it, a frame shows
// clutter only and is dropped.
constexpr double kOutlierWindow = 3;

// A reference leaving more than this share of the frames without a sample around them is named.
constexpr double kUncoveredShare = 0.05;

template <class F>
std::function<Eigen::MatrixXd(std::size_t)> columns(const Obs& obs, int k, F f) {
  return [obs, k, f](std::size_t v) {
    Eigen::MatrixXd C(static_cast<Eigen::Index>(obs->size()), k);
    for (std::size_t i = 0; i < obs->size(); ++i) C.row(static_cast<Eigen::Index>(i)) = f((*obs)[i], v);
    return C;
  };
}


// Bearings in radians written into bearing_deg (0 ... 6.28 "degrees") pass every range check and
// leave nothing near the reference: named before any gate where every bearing lies within
// +-2 pi degrees while most reference bearings (truth) lie outside that band.
void check_bearing_units(const AzimuthData& data, const PlaneSeries& observer, const PlaneSeries& truth) {
  int n = 0, inside = 0, preds = 0, outside = 0;
  for (const auto& fr : data.frames) {
    Eigen::Vector2d po, pt;
    if (!observer.at(fr.t_s, po) || !truth.at(fr.t_s, pt)) continue;
    ++preds;
    outside += outside_radians_band(bearing_rad(pt - po));
    for (double x : fr.bearings_rad) ++n, inside += std::abs(x) <= kRadiansAsDegreesRad;
  }
  if (bearings_look_like_radians(n, inside, preds, outside))
    throw ConfigError("bearings.csv bearing_deg looks like radians: all " + std::to_string(n) +
                      " values lie within [-6.28, 6.28] while the reference bearings from truth.csv mostly lie outside");
}

// Against truth: each frame's detection nearest the true bearing within the gate.
std::vector<Ob> against_truth(const AzimuthData& data, const PlaneSeries& observer, const PlaneSeries& truth, double gate,
                              int& dropped, int& no_reference) {
  std::vector<Ob> obs;
  auto brg = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return bearing_rad(b - a); };
  for (const auto& fr : data.frames) {
    Eigen::Vector2d po, pt, po_a, po_b, pt_a, pt_b;
    const double h = 0.5;  // [s] half-step of the central difference of the bearing rate
    if (!observer.at(fr.t_s, po) || !truth.at(fr.t_s, pt) || !observer.at(fr.t_s - h, po_a) ||
        !observer.at(fr.t_s + h, po_b) || !truth.at(fr.t_s - h, pt_a) || !truth.at(fr.t_s + h, pt_b)) {
      ++dropped, ++no_reference;
      continue;
    }
    const double bt = brg(po, pt), best = nearest_wrapped(fr.bearings_rad, bt);
    if (!(std::abs(best) <= kOutlierWindow * gate)) {
      ++dropped;
      continue;
    }
    Ob x;
    x.t = fr.t_s;
    x.r = best;
    x.rate = wrap_pi(brg(po_b, pt_b) - brg(po_a, pt_a)) / (2 * h);
    x.range = (pt - po).norm();
    obs.push_back(x);
  }
  return obs;
}

// Against a CV track fitted to the bearings (fitted on the frames within the gate).
std::vector<Ob> against_fitted(const std::vector<TrackObs>& tobs, const TrackFit& fit, double gate) {
  std::vector<Ob> obs;
  for (std::size_t k = 0; k < tobs.size(); ++k) {
    const double best = nearest_wrapped(tobs[k].bearings_rad, fit.track.bearing(tobs[k]));
    if (!(std::abs(best) <= kOutlierWindow * gate)) continue;
    Ob x;
    x.t = tobs[k].t_s;
    x.k = k;
    x.r = best;
    x.rate = fit.track.bearing_rate(tobs[k]);
    x.range = (fit.track.at(x.t) - tobs[k].o_F).norm();
    x.J = fit.track.jacobian(tobs[k]);
    obs.push_back(x);
  }
  return obs;
}

// The held-out track (nuisance and manoeuvres of the out-of-sample fit, linearised about the
// full fit) against truth after the split.
void extrapolated_track_gain(const Problem& pb, const SearchResult& r, const CvTrack& full, const PlaneSeries& truth,
                             double split, double t_end, DiagnoseReport& rep) {
  auto track = [&](const Eigen::VectorXd& beta, bool extended, double t) {
    // p(t) = p_full(t) + dp0 + dv (t - t_ref) + sum_m dv_m (t - t_m)+
    Eigen::Vector2d p = full.at(t) + beta.segment<2>(0) + beta.segment<2>(2) * (t - full.t_ref_s);
    if (!extended) return p;
    Eigen::Index col = 4;
    for (const auto& [e, v] : r.holdout_entries) {
      const Candidate& c = pb.catalogue[e];
      if (c.name == "target_maneuver") p += beta.segment<2>(col) * ramp(t, c.scan[v]);
      col += static_cast<Eigen::Index>(c.params.size());
    }
    return p;
  };
  ChannelGain g;
  g.unit = "m";
  double a = 0, b = 0;
  for (std::size_t i = 0; i < pb.size(); ++i) {
    const double t = pb.t_s[i];
    Eigen::Vector2d pt;
    if (t < split || t > t_end || !truth.at(t, pt)) continue;
    a += (track(r.nominal_oos_beta, false, t) - pt).squaredNorm();
    b += (track(r.extended_oos_beta, true, t) - pt).squaredNorm();
    ++g.n;
  }
  if (g.n == 0) return;
  g.nominal_rms = std::sqrt(a / g.n);
  g.extended_rms = std::sqrt(b / g.n);
  rep.gain["truth_position_m"] = g;
}

void add_target_model(const AzimuthData& data, const LocalLevelFrame& F, const UavDiagnoseOptions& o, DiagnoseReport& rep) {
  TargetModelOptions to;
  to.search = o.search;
  const TargetModelResult tm = test_target_model({{"object", data.truth}}, F, to);
  for (const auto& m : tm.maneuvers) {
    EffectResult e;
    e.name = m.name;
    e.params = {"t_s", m.params[0], m.params[1]};
    e.estimate = {m.scan_value, m.estimate[0], m.estimate[1]};
    e.stderr_ = {m.scan_se, m.stderr_[0], m.stderr_[1]};
    e.evidence_lr = m.lr;
    e.log10_p = m.log10_p;
    e.kept_lr = m.kept_lr;
    e.kept_log10_p = m.kept_log10_p;
    e.delta_bic = m.delta_bic;
    e.note = "the reference track (truth) departs from constant velocity here (tested on the track itself)";
    rep.effects.push_back(e);
  }
  for (const auto& n : tm.notes) rep.reference += "; target model: " + n;
}

// Checks the options and that the observer has a track; throws ConfigError naming the fault.
void check_options(const AzimuthData& data, const UavDiagnoseOptions& o) {
  if (!(o.gate_deg > 0 && o.gate_deg <= 90)) throw ConfigError("diagnose uav: gate must be in (0, 90] deg");
  if (!(o.sigma_deg > 0)) throw ConfigError("diagnose uav: sigma must be > 0 deg");
  if (!(o.split_fraction > 0.2 && o.split_fraction < 0.9)) throw ConfigError("diagnose uav: split fraction must be in (0.2, 0.9)");
  if (o.maneuver_grid < 2) throw ConfigError("diagnose uav: manoeuvre grid must be >= 2");
  if (data.observer.size() < 2) throw ConfigError("diagnose uav: observer.csv needs at least 2 rows");
}

// The bearing residuals against the reference (truth or the fitted track), the catalogue of
// the effects, and the covariates: estimation frames before split; the frames span
// [t0, t0 + span] [s].
Problem uav_problem(const Obs& obs, const UavDiagnoseOptions& o, bool with_truth, double t0, double span, double split) {
  const std::vector<Ob>& ob = *obs;
  Problem pb;
  pb.channels.push_back({"bearing", "", "", "rad", o.sigma_deg * kDegToRad});
  const auto n = static_cast<Eigen::Index>(ob.size());
  pb.nuisance = Eigen::MatrixXd(n, with_truth ? 0 : 4);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Ob& x = ob[static_cast<std::size_t>(i)];
    pb.channel.push_back(0);
    pb.t_s.push_back(x.t);
    pb.y.push_back(x.r);
    pb.estimation.push_back(x.t < split);
    if (!with_truth) pb.nuisance.row(i) = x.J.transpose();
  }
  if (!with_truth) pb.nuisance_names = {"object p0_north_m", "object p0_east_m", "object v_north_mps", "object v_east_mps"};
  using V = std::size_t;
  // The sensor's entries are the simulator's own columns (common/physics/bearing_effect_columns.hpp).
  namespace fx = bearing_effect;
  pb.catalogue.push_back({"bearing_bias", {}, {"rad"}, "a constant on the bearings", "", {},
                          columns(obs, 1, [](const Ob& x, V) { return fx::bias(x.geometry()); })});
  pb.catalogue.push_back({"time_offset", {}, {"s"}, "the bearing rate", "", {},
                          columns(obs, 1, [](const Ob& x, V) { return fx::time_offset(x.geometry()); })});
  pb.catalogue.push_back({"bias_drift", {}, {"rad_per_s"}, "time", "", {},
                          columns(obs, 1, [t0](const Ob& x, V) { return fx::bias_drift(x.geometry(), t0); })});
  pb.catalogue.back().shape = true;  // a shape in time, not a physical cause
  std::vector<double> periods;
  for (double T = 4; T <= span / 3; T *= 1.05) periods.push_back(T);
  if (!periods.empty())
    pb.catalogue.push_back({"periodic", {}, {"sin_rad", "cos_rad"}, "an oscillation of the bearings", "period_s", periods,
                            columns(obs, 2, [periods](const Ob& x, V v) { return fx::periodic(x.geometry(), periods[v]); })});
  if (!with_truth) {
    std::vector<double> times;
    for (int i = 1; i <= o.maneuver_grid; ++i) times.push_back(t0 + span * i / (o.maneuver_grid + 1));
    // A velocity change dv at t_m: p(t) += dv (t - t_m)+, so d bearing / d dv = J_p (t - t_m)+.
    pb.catalogue.push_back({"target_maneuver", {}, {"dv_north_mps", "dv_east_mps"},
                            "a change of the object's velocity (bearing curvature)", "t_s", times,
                            columns(obs, 2, [times](const Ob& x, V v) {
                              Eigen::RowVectorXd r(2);
                              r << x.J(0) * ramp(x.t, times[v]), x.J(1) * ramp(x.t, times[v]);
                              return r;
                            })});
  }
  std::vector<double> range, rate, time;
  for (const auto& x : ob) range.push_back(x.range), rate.push_back(x.rate), time.push_back(x.t - t0);
  pb.covariates = {{"range", range}, {"bearing rate", rate}, {"time", time}};
  return pb;
}

// Against the fitted track: what it leaves unexplained (an object range the observer's path
// does not observe; many frames without a detection near the track), into rep.unexplained.
void add_fitted_track_notes(const std::vector<Ob>& ob, const std::vector<TrackObs>& tobs, const TrackFit& full,
                            const UavDiagnoseOptions& o, DiagnoseReport& rep) {
  // Observability: the relative SE of the object's range along the line of sight from the
  // observer's mean position; bearings fix range only through the observer's own motion.
  Eigen::Vector2d o_mean = Eigen::Vector2d::Zero();
  for (const auto& x : ob) o_mean += tobs[x.k].o_F;
  o_mean /= static_cast<double>(ob.size());
  const Eigen::Vector2d los = full.track.p0_F - o_mean;
  const double R = los.norm();
  const double se_R = std::sqrt((los / R).dot(full.cov.topLeftCorner<2, 2>() * (los / R)));
  if (!(se_R < 0.2 * R))
    rep.unexplained.push_back("the object's range is not observable from this observer path (range " + short_num(R) +
                              " m +- " + short_num(se_R) + " m): the fitted track, the gain and range-dependent "
                              "effects are unreliable; the observer must manoeuvre (or use truth)");
  const double frac = 1.0 - static_cast<double>(full.n_associated) / static_cast<double>(std::max<std::size_t>(1, tobs.size()));
  if (frac > 0.2)
    rep.unexplained.push_back(short_num(100 * frac) + " % of the frames with detections have none within " +
                              short_num(o.gate_deg) + " deg of the fitted constant-velocity track");
}

}  // namespace

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o) {
  check_options(data, o);
  const bool with_truth = data.truth.size() >= 2 && !o.ignore_truth;
  DiagnoseReport rep;
  rep.kind = "uav";
  const LocalLevelFrame F(data.observer.front().g, 0.0);  // x north, z east
  const PlaneSeries observer(data.observer, F);
  const PlaneSeries truth(data.truth, F);
  const double gate = o.gate_deg * kDegToRad;

  std::vector<TrackObs> tobs;
  TrackFit full;
  auto obs = std::make_shared<std::vector<Ob>>();
  if (with_truth) {
    check_bearing_units(data, observer, truth);
    if (o.check_references) check_bearing_references(data, observer, truth, kOutlierWindow * gate);
    rep.reference = "truth (truth.csv)";
    int no_reference = 0;
    *obs = against_truth(data, observer, truth, gate, rep.plots_dropped, no_reference);
    // a reference that covers part of the frames: the rest left out, and said so (beyond the few
    // frames at the ends, whose bearing rate needs a sample half a second either side)
    if (no_reference > kUncoveredShare * static_cast<double>(data.frames.size()))
      rep.reference += ", over " + short_num(std::max(truth.t_first(), observer.t_first())) + " to " +
                       short_num(std::min(truth.t_last(), observer.t_last())) + " s of the frames' " +
                       short_num(data.frames.front().t_s) + " to " + short_num(data.frames.back().t_s) + " s: " +
                       std::to_string(no_reference) + " frames without an observer or truth sample around them left out";
  } else {
    TrackFitOptions fo;
    fo.gate_deg = o.gate_deg;
    fo.seed = o.seed;
    tobs = track_observations(data, F);
    full = fit_cv_track(tobs, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), fo);
    rep.reference = "constant-velocity track fitted to the bearings (no truth used); object at t = " +
                    short_num(full.track.t_ref_s) + " s: " + short_num(full.track.p0_F.x()) + " m north, " +
                    short_num(full.track.p0_F.y()) + " m east of the first observer sample, velocity (" +
                    short_num(full.track.v_F.x()) + ", " + short_num(full.track.v_F.y()) + ") m/s";
    *obs = against_fitted(tobs, full, gate);
    rep.plots_dropped = static_cast<int>(data.frames.size() - obs->size());
  }
  rep.plots_used = static_cast<int>(obs->size());
  if (obs->size() < 30)
    throw ConfigError(std::string("diagnose uav: fewer than 30 frames with a detection near the ") +
                      (with_truth ? "truth" : "fitted track"));
  const std::vector<Ob>& ob = *obs;
  const double t0 = ob.front().t, span = ob.back().t - t0;
  const double split = t0 + o.split_fraction * span;
  rep.split_time_s = split;

  const Problem pb = uav_problem(obs, o, with_truth, t0, span, split);
  const auto n = static_cast<Eigen::Index>(ob.size());

  check_limit_entries(pb, o.search.injection, "diagnose uav");
  const SearchResult r = search_effects(pb, o.search);
  add_search_findings(pb, r, rep);
  if (with_truth && o.test_target_model) add_target_model(data, F, o, rep);
  if (!with_truth && data.truth.size() >= 2) extrapolated_track_gain(pb, r, full.track, truth, split, ob.back().t, rep);

  if (!with_truth) add_fitted_track_notes(ob, tobs, full, o, rep);
  const double sigma = std::sqrt(r.noise[0].fit.params.s2);
  if (gate < 3 * sigma)
    rep.unexplained.push_back("the association gate (" + short_num(o.gate_deg) + " deg) is narrower than 3 sigma of the fitted noise (" +
                              short_num(3 * sigma / kDegToRad) + " deg): detections of the object are lost; widen --gate-deg");
  const std::vector<char> flags = outlier_flags(pb, r);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Ob& x = ob[static_cast<std::size_t>(i)];
    rep.rows.push_back({x.t, {x.r, x.rate, x.range}, {0, 0, 0}, {r.effect_fit(i), 0, 0}, flags[static_cast<std::size_t>(i)] != 0});
  }
  return rep;
}

}  // namespace rnav
