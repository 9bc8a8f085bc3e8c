#include "estimators/diagnosis/multi_association.hpp"

#include "estimators/diagnosis/assignment.hpp"
#include "common/io/config.hpp"
#include "estimators/diagnosis/gross_check.hpp"
#include "estimators/diagnosis/plane_series.hpp"
#include "estimators/diagnosis/rotation_scans.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace rnav {

namespace {

// Robust standard error of a median: sigma = 1.4826 MAD for Gaussian residuals, and the median's
// SE is sqrt(pi/2) times the mean's: se = sqrt(pi/2) 1.4826 MAD / sqrt(n).
constexpr double kMadToSigma = 1.4826;
constexpr double kMedianSeFactor = 1.2533141373155003;  // sqrt(pi/2)
// A gate shift is applied only beyond both: kShiftMinSe of its standard errors (not noise) and
// kShiftMinGateFraction of the final gate: only a bias larger than the gate itself, which the
// gate would otherwise lose. At a quarter or half of the gate the real Autoferry cameras' and
// radar's offsets (a 31 m hull seen away from its GNSS antenna, a late radar clock; not one
// common bias) moved their gates onto other parts of the scene: scenario 4's IR associated 426
// detections of Gunnerus instead of 186 and 11 of Havfruen instead of 44, scenario 5's radar 53
// of both boats instead of 163.
constexpr double kShiftMinSe = 3;
constexpr double kShiftMinGateFraction = 1.0;
constexpr double kMaxWideGateDeg = 90;  ///< [deg] upper limit of wide_gate_bearing_deg: residuals stay far from +-pi
constexpr int kMinPairsFloor = 3;       ///< lower limit of recentre_min_pairs: a median and a MAD need 3
constexpr double kMinPredRange = 1.0;   ///< [m] a prediction nearer the observer has no bearing

struct Pred {
  std::string target;
  Eigen::Vector2d p, v;
  double interp_sd_m = 0, interval_s = 0;  // AssociatedDetection::ref_interp_sd_m, ref_interval_s
};

// One scan: the rows of one sensor with one t_s (or, for a sensor read as rotations, the rows of
// one rotation, each at its own time), and the reference geometry at its time (frame F, (north, east)).
struct Scan {
  std::string sensor;
  double t = 0;                   // [s] the scan's time (a rotation's middle)
  std::vector<std::size_t> rows;  // the rows with a detection
  std::vector<double> dt;         // [s] per row: its time minus t (0 for a scan stamped once)
  bool ranged = false;
  Eigen::Vector2d po, vo;   // [m], [m/s] the observer's position and velocity
  double gamma = 0;         // [rad] the observer's local north, clockwise from the frame's north
  std::vector<Pred> preds;  // targets with a reference at t_s; empty without the observer's
};


// Target minus observer for row i of scan s, at the row's own time (the scan's prediction moved
// along both velocities by the row's dt; exactly the scan's own without dt).
Eigen::Vector2d rel(const Scan& s, std::size_t i, const Pred& pr) {
  const double dt = s.dt[i];
  if (dt == 0) return pr.p - s.po;
  return (pr.p + dt * pr.v) - (s.po + dt * s.vo);
}

// The same as a sensor whose clock is tau [s] off sees it (its stamp minus true time): the row
// stamped t shows the target where it was at t - tau,
//   d(t - tau) = d(t) - tau (v_T - v_O)   (first order, as sensor_clock in multi_effect_columns.hpp);
// exactly rel() for tau = 0.
Eigen::Vector2d rel(const Scan& s, std::size_t i, const Pred& pr, double tau) {
  return tau == 0 ? rel(s, i, pr) : Eigen::Vector2d(rel(s, i, pr) - tau * (pr.v - s.vo));
}

// The relative position d moved by a bearing shift db [rad] and a range shift dr [m] about the observer:
//   d' = max(0, |d| + dr) (cos(atan2(d_e, d_n) + db), sin(atan2(d_e, d_n) + db));  d itself without shift.
Eigen::Vector2d shifted(const Eigen::Vector2d& d, double db, double dr) {
  if (db == 0 && dr == 0) return d;
  const double b = bearing_rad(d) + db, r = std::max(0.0, d.norm() + dr);
  return r * Eigen::Vector2d(std::cos(b), std::sin(b));
}

// Distance of row i's detection from the relative prediction d (metres for range sensors,
// radians for bearing-only; its bearing turned into the frame).
double distance(const Detection& dk, const Scan& s, const Eigen::Vector2d& d) {
  const double b_F = dk.bearing_rad + s.gamma;
  if (s.ranged) return (dk.range_m * Eigen::Vector2d(std::cos(b_F), std::sin(b_F)) - d).norm();
  return std::abs(wrap_pi(b_F - bearing_rad(d)));
}

// Separation of two relative predictions, in the units of distance().
double separation(const Scan& s, const Eigen::Vector2d& da, const Eigen::Vector2d& db) {
  return s.ranged ? (da - db).norm() : std::abs(wrap_pi(bearing_rad(da) - bearing_rad(db)));
}

}  // namespace

// Gross checks of each sensor's units against the reference geometry, before any gate: a unit
// mixed up passes every range check and either associates nothing or comes out as a wrong bias
// (ranges in km on the Autoferry lidar: a range bias of -77 m). Per sensor, over its detections
// in scans with a reference:
//   bearings: bearings_look_like_radians (gross_check.hpp): every |bearing| within 2 pi degrees
//             while most predicted bearings lie outside that band;
//   ranges:   per scan and target, of the detections within kUnitsBearingDeg of its predicted
//             bearing the ratio r / |d| nearest 1; their median outside [1 / kMaxRangeScale,
//             kMaxRangeScale] is an error, the likely unit named (range_unit_of). (The detection nearest in bearing, as first written, took the
//             real Autoferry radar's clutter on a boat's bearing: a median of 2.08.)
namespace {

constexpr double kUnitsBearingDeg = 10;  // [deg] a detection compared with the target this near in bearing
// Per range sensor: per scan and target, the ratio r / |d| nearest 1 of the detections within
// kUnitsBearingDeg of the target's predicted bearing (clutter at other ranges on its bearing, a
// shore or a wake, does not count).
std::map<std::string, std::vector<double>> range_ratios(const std::vector<Scan>& scans, const std::vector<Detection>& det) {
  std::map<std::string, std::vector<double>> out;
  for (const Scan& s : scans) {
    if (s.preds.empty() || s.rows.empty() || !s.ranged) continue;
    for (const auto& pr : s.preds) {
      if ((pr.p - s.po).norm() < kMinPredRange) continue;
      double best = INFINITY, q = 0;
      for (std::size_t i = 0; i < s.rows.size(); ++i) {
        const auto k = s.rows[i];
        const Eigen::Vector2d d = rel(s, i, pr);
        if (std::abs(wrap_pi(det[k].bearing_rad + s.gamma - bearing_rad(d))) > kUnitsBearingDeg * kDegToRad) continue;
        const double r = det[k].range_m / d.norm();
        if (r > 0 && std::abs(std::log(r)) < best) best = std::abs(std::log(r)), q = r;
      }
      if (q > 0) out[s.sensor].push_back(q);
    }
  }
  return out;
}

// explain_mismatch: called where the ranges match no unit, its text appended to the error (what
// else explains the mismatch: a time shift, references far from the observer; "" for nothing).
void check_units(const std::vector<Scan>& scans, const std::vector<Detection>& det,
                 const std::function<std::string()>& explain_mismatch) {
  struct Acc {
    int bearings = 0, inside = 0, preds_outside = 0, preds = 0;
    std::vector<double> ratio;
  };
  std::map<std::string, Acc> acc;
  for (const Scan& s : scans) {
    if (s.preds.empty() || s.rows.empty()) continue;
    Acc& a = acc[s.sensor];
    for (const auto& pr : s.preds) {
      ++a.preds;
      a.preds_outside += outside_radians_band(wrap_pi(bearing_rad(pr.p - s.po) - s.gamma));
    }
    for (auto k : s.rows) {
      ++a.bearings;
      if (std::abs(det[k].bearing_rad) <= kRadiansAsDegreesRad) ++a.inside;
    }
  }
  for (auto& [sensor, r] : range_ratios(scans, det)) acc[sensor].ratio = std::move(r);
  for (auto& [sensor, a] : acc) {
    if (bearings_look_like_radians(a.bearings, a.inside, a.preds, a.preds_outside))
      throw ConfigError("detections.csv bearing_deg of sensor " + sensor + " looks like radians: all " +
                        std::to_string(a.bearings) + " values lie within [-6.28, 6.28] while the targets' reference "
                        "bearings mostly lie outside");
    if (static_cast<int>(a.ratio.size()) < kMinUnitSamples) continue;
    const double q = median(a.ratio);
    if (q >= 1 / kMaxRangeScale && q <= kMaxRangeScale) continue;
    const std::string unit = range_unit_of(q);
    throw ConfigError("detections.csv range_m of sensor " + sensor + " " +
                      (unit.empty() ? std::string("does not match the reference geometry") : "looks like " + unit) +
                      ": median ratio to the range of a target on its bearing " + short_num(q) + " over " +
                      std::to_string(a.ratio.size()) + " target scans (expected 1; a range off by more than 25 % is no sensor effect)" +
                      (unit.empty() ? explain_mismatch() : std::string()));
  }
}

// The checks of associate()'s options.
void check_options(const AssociationOptions& o) {
  if (!(o.gate_bearing_deg > 0 && o.gate_bearing_deg <= 45)) throw ConfigError("association: gate_bearing_deg must be in (0, 45]");
  if (!(o.gate_position_m > 0)) throw ConfigError("association: gate_position_m must be > 0");
  if (!(o.reference_max_gap_s > 0) || !std::isfinite(o.reference_max_gap_s))
    throw ConfigError("association: reference_max_gap_s must be finite and > 0");
  if (!(o.reference_accel_mps2 == -1 || (o.reference_accel_mps2 >= 0 && std::isfinite(o.reference_accel_mps2))))
    throw ConfigError("association: reference_accel_mps2 must be -1 (each target's own) or finite and >= 0");
  if (!(o.reference_jump_accel_mps2 >= 0) || !std::isfinite(o.reference_jump_accel_mps2))
    throw ConfigError("association: reference_jump_accel_mps2 must be finite and >= 0 (0: no jump check)");
  if (o.recentre_gates) {
    if (!(o.wide_gate_bearing_deg > 0 && o.wide_gate_bearing_deg <= kMaxWideGateDeg))
      throw ConfigError("association: wide_gate_bearing_deg must be in (0, 90]");
    if (!(o.wide_gate_position_m > 0) || !std::isfinite(o.wide_gate_position_m))
      throw ConfigError("association: wide_gate_position_m must be finite and > 0");
    if (o.recentre_min_pairs < kMinPairsFloor) throw ConfigError("association: recentre_min_pairs must be >= 3");
    if (o.max_passes < 1) throw ConfigError("association: max_passes must be >= 1");
  }
  if (!(o.ambiguous_gates > 0) || !std::isfinite(o.ambiguous_gates))
    throw ConfigError("association: ambiguous_gates must be finite and > 0");
}

// One unambiguous first-pass pair (or a pass's associated pair): its residuals and how fast the
// reference geometry moves, which a sensor clock turns into residual (sensor_clock in
// multi_effect_columns.hpp).
struct PairResidual {
  std::string target;
  double bearing_rad = 0;         // wrap(b_meas - b_pred) [rad]
  double bearing_rate_radps = 0;  // beta_dot = d b_pred / dt along the relative velocity [rad/s]
  double range_m = 0;             // r_meas - |d| [m], range sensors
  double range_rate_mps = 0;      // r_dot = d |d| / dt [m/s], range sensors
  double pred_range_m = 0;        // |d| [m]
};

// One sensor's unambiguous first-pass residuals (or the pairs a pass associated).
struct WideResiduals {
  std::vector<PairResidual> pairs;
  bool ranged = false;
};

// A shift and its standard error (value 0: not applied).
struct ShiftEstimate {
  double value = 0, se = 0;
};

// The targets' medians of one residual (targets with kMinTargetPairs pairs or more).
std::vector<double> target_medians(const WideResiduals& w, double PairResidual::*field) {
  std::map<std::string, std::vector<double>> by_target;
  for (const PairResidual& p : w.pairs) by_target[p.target].push_back(p.*field);
  std::vector<double> m;
  for (const auto& [t, v] : by_target)
    if (static_cast<int>(v.size()) >= kMinTargetPairs) m.push_back(median(v));
  return m;
}

// Across targets: the median of the targets' medians, beyond kShiftMinSe standard errors of a
// median over targets; else 0.
ShiftEstimate shift_across_targets(const std::vector<double>& m) {
  const double c = median(m);
  std::vector<double> dev(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) dev[i] = std::abs(m[i] - c);
  const double se = kMedianSeFactor * kMadToSigma * median(dev) / std::sqrt(static_cast<double>(m.size()));
  return {std::abs(c) > kShiftMinSe * se ? c : 0.0, se};
}

// Per sensor: (bearing [rad], range [m], clock [s]) shifts for gating, and whether they are
// judged across targets (and iterated).
struct SensorShift {
  ShiftEstimate bearing, range, clock;
  bool across_targets = false;
  int targets = 0;
  bool iterate = false;  // re-estimated from each pass's pairs (across targets, or a fit on pairs applied)
  std::string clock_refused;  // a significant pooled clock left out, and why (clock_disagreement); "" otherwise
  double clock_fitted_s = 0;  // [s] that refused clock's value
  std::string refused;        // a fitted shift beyond what the sensor can be off by (shift_bounds); "" otherwise
};

// What a sensor can physically be off by, per kind (the format tells range sensors from
// bearing-only ones). A fitted gate shift beyond it is refused - the gates stay on the prediction
// - and named: it comes from pairs that are not the targets' (a reference that ends while the
// target's echoes go on, taken for another target's; clutter), not from the sensor.
//   bearing-only sensors (cameras): bearing 15 deg (a camera's mount yaw plus the heading
//     reference's offset; the largest measured here, Autoferry scenario 5's IR, is 6.1-6.7 deg)
//   range sensors (radar, lidar): bearing 10 deg (a radar's heading-line alignment, a lidar's
//     mount yaw), range 100 m (a radar's zero-range delay of 0.67 us; a lidar's is centimetres) or
//     a quarter of the pairs' median range where that is more (a range gain shows in the
//     constant shift as gain times range; beyond 25 % the unit check refuses the ranges)
//   both: clock 5 s (a scan stamped at its start or end, a few seconds' rotation; the largest
//     measured here is 1.8 s)
struct ShiftBounds {
  double bearing_rad, range_m, clock_s;
  const char* kind;
};
constexpr double kShiftRangeM = 100, kShiftRangeShare = 0.25;
ShiftBounds shift_bounds(bool ranged, double median_range_m) {
  if (ranged) return {10 * kDegToRad, std::max(kShiftRangeM, kShiftRangeShare * median_range_m), 5, "a range sensor"};
  return {15 * kDegToRad, INFINITY, 5, "a bearing-only sensor"};
}

// "" when the shifts are within the bounds; else what is beyond them, for the report.
std::string beyond_bounds(const SensorShift& sh, const WideResiduals& w) {
  const bool ranged = w.ranged;
  std::vector<double> ranges;
  for (const PairResidual& q : w.pairs) ranges.push_back(q.pred_range_m);
  const ShiftBounds b = shift_bounds(ranged, ranges.empty() ? 0.0 : median(ranges));
  if (std::abs(sh.bearing.value) <= b.bearing_rad && std::abs(sh.range.value) <= b.range_m &&
      std::abs(sh.clock.value) <= b.clock_s)
    return "";
  std::ostringstream why;
  why << "the fitted shift (" << short_num(sh.bearing.value / kDegToRad) << " deg";
  if (ranged) why << ", " << short_num(sh.range.value) << " m";
  if (sh.clock.value != 0) why << ", a clock of " << short_num(sh.clock.value) << " s";
  why << ") is beyond what " << b.kind << " can be off by (" << short_num(b.bearing_rad / kDegToRad) << " deg";
  if (ranged) why << ", " << short_num(b.range_m) << " m";
  why << ", " << short_num(b.clock_s) << " s): its pairs are not its targets' (a reference that ends while the target's "
      << "echoes go on, clutter)";
  return why.str();
}
using Shifts = std::map<std::string, SensorShift>;

// Huber's M-estimate with its scale per group of rows (bearings, ranges): the rows'
// residuals e_k = y_k - x_k theta are taken in units of their group's robust sd
// s_g = 1.4826 MAD(e over the group), u_k = e_k / s_g, and theta minimises sum rho(u_k) with
// rho(u) = u^2 / 2 for |u| <= c, c |u| - c^2 / 2 beyond (iteratively reweighted least squares,
// weights w = min(1, c / |u|), s_g re-estimated each iteration; convex in theta for given
// scales, so the start only sets the path). Covariance (Huber 1981, 7.6):
//   cov(theta) = K (X_s' X_s)^-1,  K = [sum psi(u)^2 / (n - p)] / [sum psi'(u) / n]^2,
// X_s the rows divided by their group's scale, psi(u) = max(-c, min(c, u)), psi' = 1 inside c.
// It counts every pair as independent, as the median's standard error above does.
constexpr double kHuberC = 1.345;         // 95 % efficiency at Gaussian noise, bounded influence of clutter and gross errors
constexpr int kMaxRobustIterations = 100; // IRLS steps at most: IRLS converges linearly; the cap bounds a fit that does not
constexpr double kRobustStepSe = 1e-6;    // converged: no parameter moved by more than this share of its SE
constexpr double kMinScale = 1e-12;       // [rad or m] floor of a group's scale: noise-free data keep finite weights
constexpr double kMinRcond = 1e-12;       // a normal matrix nearer singular than this has no fit (a rate without spread)
struct RobustFit {
  Eigen::VectorXd theta, se;
  bool ok = false;
};
RobustFit huber_fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const std::vector<int>& group, Eigen::VectorXd theta) {
  const Eigen::Index n = X.rows(), p = X.cols();
  RobustFit f;
  if (n <= p) return f;
  int groups = 0;
  for (int g : group) groups = std::max(groups, g + 1);
  Eigen::VectorXd scale(groups), u(n);
  Eigen::MatrixXd cov_unscaled;
  for (int it = 0; it < kMaxRobustIterations; ++it) {
    const Eigen::VectorXd e = y - X * theta;
    for (int g = 0; g < groups; ++g) {
      std::vector<double> eg;
      for (Eigen::Index k = 0; k < n; ++k)
        if (group[k] == g) eg.push_back(e(k));
      scale(g) = std::max(kMadToSigma * median_abs(eg), kMinScale);
    }
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p, p), N = Eigen::MatrixXd::Zero(p, p);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(p);
    for (Eigen::Index k = 0; k < n; ++k) {
      const double s = scale(group[k]);
      u(k) = e(k) / s;
      const double w = std::abs(u(k)) <= kHuberC ? 1.0 : kHuberC / std::abs(u(k));
      const Eigen::RowVectorXd xs = X.row(k) / s;
      A += w * xs.transpose() * xs;
      N += xs.transpose() * xs;
      rhs += w * xs.transpose() * (y(k) / s);
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A), ldlt_n(N);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > kMinRcond) || !(ldlt_n.rcond() > kMinRcond)) return f;
    const Eigen::VectorXd next = ldlt.solve(rhs);
    cov_unscaled = ldlt_n.solve(Eigen::MatrixXd::Identity(p, p));
    const Eigen::VectorXd step = (next - theta).cwiseAbs().cwiseQuotient(cov_unscaled.diagonal().cwiseSqrt());
    theta = next;
    if (step.maxCoeff() < kRobustStepSe) break;
  }
  const Eigen::VectorXd e = y - X * theta;
  double psi2 = 0, dpsi = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double v = e(k) / scale(group[k]);
    psi2 += std::pow(std::clamp(v, -kHuberC, kHuberC), 2);
    dpsi += std::abs(v) <= kHuberC;
  }
  if (dpsi == 0) return f;
  const double K = (psi2 / static_cast<double>(n - p)) / std::pow(dpsi / static_cast<double>(n), 2);
  f.theta = theta;
  f.se = (K * cov_unscaled.diagonal()).cwiseSqrt();
  f.ok = f.theta.allFinite() && f.se.allFinite();
  return f;
}

// A sensor's common error fitted on pairs: bearing bias b [rad], range bias r [m] (range
// sensors) and clock tau [s] (its stamp minus true time: a detection stamped t shows the target
// where it was at t - tau, sensor_clock in multi_effect_columns.hpp), jointly on
//   bearing residual  wrap(b_meas - b_pred) = b - beta_dot tau   (every pair)
//   range residual    r_meas - |d|          = r - r_dot tau      (range sensors)
// by Huber's M-estimate (huber_fit), started at the residuals' medians and tau = 0. The clock
// stays in only beyond kShiftMinSe of its SE; without it b and r are refitted alone (a clock
// without spread in the rates takes up a constant). Each of b, r, tau is applied only beyond
// kShiftMinSe of its SE (0 otherwise; its SE kept). A clock on moving targets whose bearings turn
// the same way shifts every residual by -beta_dot tau: a median constant takes the bias plus the
// clock's share at the median rate (Autoferry scenario 5 simulated with its IR camera's 6.7 deg
// and -1.78 s alone, white noise: boats turning at -0.4 to -2.8 deg/s, a median of 4.2-4.5 deg
// over the first pass's pairs, this fit 6.75-6.86 deg and -1.78 to -1.87 s), and a gate centred
// on the median truncates the residuals on one side.
// The rows of the fit below on a set of pairs: columns b, [r,] tau; bearing rows first, group 0;
// range rows (range sensors) group 1; the start at the residuals' medians and tau = 0.
struct PairDesign {
  Eigen::MatrixXd X;
  Eigen::VectorXd y, start;
  std::vector<int> group;
};
PairDesign pair_design(const std::vector<const PairResidual*>& pairs, bool ranged) {
  const Eigen::Index n = static_cast<Eigen::Index>(pairs.size());
  const Eigen::Index p = ranged ? 3 : 2;
  PairDesign d;
  d.X = Eigen::MatrixXd::Zero(ranged ? 2 * n : n, p);
  d.y.resize(d.X.rows());
  d.group.assign(static_cast<std::size_t>(d.X.rows()), 0);
  std::vector<double> rb, rr;
  for (Eigen::Index i = 0; i < n; ++i) {
    const PairResidual& q = *pairs[static_cast<std::size_t>(i)];
    d.X(i, 0) = 1, d.X(i, p - 1) = -q.bearing_rate_radps, d.y(i) = q.bearing_rad;
    rb.push_back(q.bearing_rad);
    if (!ranged) continue;
    d.X(n + i, 1) = 1, d.X(n + i, 2) = -q.range_rate_mps, d.y(n + i) = q.range_m;
    d.group[static_cast<std::size_t>(n + i)] = 1;
    rr.push_back(q.range_m);
  }
  d.start = Eigen::VectorXd::Zero(p);
  if (n > 0) d.start(0) = median(rb);
  if (ranged && n > 0) d.start(1) = median(rr);
  return d;
}

// A clock fitted on the pooled pairs is one sensor's only if every target says so: a per-target
// offset (a reference antenna away from the hull's centre, a target's own positioning error)
// whose residual correlates with that target's bearing rate fits a clock too, of another size on
// each target. Each target with kMinTargetPairs pairs or more gets its own fit of b_k, [r_k,]
// tau_k (huber_fit); with m >= kMinClockTargets of them the clocks must agree:
//   X^2 = sum_k (tau_k - tau_w)^2 / se_k^2,  tau_w = sum_k tau_k / se_k^2 / sum_k 1 / se_k^2,
// refused when P(chi2(m - 1) > X^2) < kClockAgreementP. With fewer targets the clock cannot be
// told from one target's own offset and is refused. Returns "" when it agrees, else why not.
// The SEs count every pair as independent: correlated noise within a target makes them too
// small, so such a target's clock disagrees sooner and the clock is left out (the gate then
// sits on the bias-only fit, as without a clock).
constexpr int kMinClockTargets = 2;
constexpr double kClockAgreementP = 0.01;
std::string clock_disagreement(const WideResiduals& w) {
  std::map<std::string, std::vector<const PairResidual*>> by_target;
  for (const PairResidual& q : w.pairs) by_target[q.target].push_back(&q);
  std::vector<std::pair<std::string, ShiftEstimate>> tau;
  for (const auto& [target, pairs] : by_target) {
    if (static_cast<int>(pairs.size()) < kMinTargetPairs) continue;
    const PairDesign d = pair_design(pairs, w.ranged);
    const RobustFit f = huber_fit(d.X, d.y, d.group, d.start);
    const Eigen::Index k = d.X.cols() - 1;
    if (f.ok && f.se(k) > 0) tau.push_back({target, {f.theta(k), f.se(k)}});
  }
  std::ostringstream why;
  why.precision(3);
  if (static_cast<int>(tau.size()) < kMinClockTargets) {
    why << "fitted on " << tau.size() << " target(s) only: a clock cannot be told from one target's own offset";
    return why.str();
  }
  double sw = 0, swt = 0;
  for (const auto& [t, e] : tau) sw += 1 / (e.se * e.se), swt += e.value / (e.se * e.se);
  const double tau_w = swt / sw;
  double x2 = 0;
  for (const auto& [t, e] : tau) x2 += std::pow((e.value - tau_w) / e.se, 2);
  const double dof = static_cast<double>(tau.size() - 1);
  if (chi2_sf(x2, dof) >= kClockAgreementP) return "";
  why << "the targets' own fits disagree (";
  for (std::size_t i = 0; i < tau.size(); ++i)
    why << (i ? ", " : "") << tau[i].first << " " << tau[i].second.value << " +- " << tau[i].second.se << " s";
  why << "; chi2 = " << x2 << " on " << dof << " dof)";
  return why.str();
}

SensorShift fit_on_pairs(const WideResiduals& w) {
  const bool ranged = w.ranged;
  std::vector<const PairResidual*> all;
  for (const PairResidual& q : w.pairs) all.push_back(&q);
  const PairDesign d = pair_design(all, ranged);
  const Eigen::Index p = d.X.cols();
  SensorShift sh;
  RobustFit f = huber_fit(d.X, d.y, d.group, d.start);
  const bool clock = f.ok && std::abs(f.theta(p - 1)) > kShiftMinSe * f.se(p - 1);
  if (clock) sh.clock_refused = clock_disagreement(w);
  if (clock && sh.clock_refused.empty()) {
    sh.clock = {f.theta(p - 1), f.se(p - 1)};
  } else {
    const double tau_se = f.ok ? f.se(p - 1) : 0.0;
    const double tau_value = clock ? f.theta(p - 1) : 0.0;
    f = huber_fit(d.X.leftCols(p - 1), d.y, d.group, d.start.head(p - 1));
    sh.clock = {0.0, tau_se};
    sh.clock_fitted_s = tau_value;
    if (!f.ok) return sh;
  }
  const auto significant = [](double v, double se) { return ShiftEstimate{std::abs(v) > kShiftMinSe * se ? v : 0.0, se}; };
  sh.bearing = significant(f.theta(0), f.se(0));
  if (ranged) sh.range = significant(f.theta(1), f.se(1));
  return sh;
}

// The gating displacement of pair q under shifts sh, in the gate's units: a bearing-only
// sensor's |b - beta_dot tau| [rad]; a range sensor's distance the prediction moves [m],
//   sqrt((|d| (b - beta_dot tau))^2 + (r - r_dot tau)^2)   (to first order in the shifts).
double displacement(const PairResidual& q, const SensorShift& sh, bool ranged) {
  const double db = sh.bearing.value - q.bearing_rate_radps * sh.clock.value;
  if (!ranged) return std::abs(db);
  return std::hypot(q.pred_range_m * db, sh.range.value - q.range_rate_mps * sh.clock.value);
}

// A sensor's shifts from its residuals (first pass, or the pairs of the last pass).
// With at least kMinCommonTargets targets: medians across targets (constant shifts, no clock).
// Otherwise (first_pass): the fit on pairs (fit_on_pairs), applied only with recentre_min_pairs
// pairs and when it moves the median pair's prediction beyond kShiftMinGateFraction of the final
// gate (a bias the gate would lose); later passes (not first_pass) refine an applied fit on the
// pairs associated through its gates, which then sit where the data are and truncate both sides alike.
SensorShift sensor_shift(const WideResiduals& w, const AssociationOptions& o, bool first_pass) {
  SensorShift sh;
  const std::vector<double> mb = target_medians(w, &PairResidual::bearing_rad);
  if (static_cast<int>(mb.size()) >= kMinCommonTargets) {
    sh.across_targets = sh.iterate = true;
    sh.targets = static_cast<int>(mb.size());
    sh.bearing = shift_across_targets(mb);
    if (w.ranged) {
      const std::vector<double> mr = target_medians(w, &PairResidual::range_m);
      if (static_cast<int>(mr.size()) >= kMinCommonTargets) sh.range = shift_across_targets(mr);
    }
    sh.refused = beyond_bounds(sh, w);
    if (!sh.refused.empty()) sh.bearing.value = sh.range.value = 0, sh.iterate = false;
    return sh;
  }
  if (static_cast<int>(w.pairs.size()) < o.recentre_min_pairs) return sh;
  sh = fit_on_pairs(w);
  if (first_pass) {
    const double gate = w.ranged ? o.gate_position_m : o.gate_bearing_deg * kDegToRad;
    std::vector<double> moved_by;
    for (const PairResidual& q : w.pairs) moved_by.push_back(displacement(q, sh, w.ranged));
    if (!(median(moved_by) > kShiftMinGateFraction * gate)) {
      sh.bearing.value = sh.range.value = sh.clock.value = 0;
      sh.clock_refused.clear(), sh.clock_fitted_s = 0;  // nothing applied: nothing refused either
    }
  }
  sh.iterate = sh.bearing.value != 0 || sh.range.value != 0 || sh.clock.value != 0;
  sh.refused = beyond_bounds(sh, w);
  if (!sh.refused.empty()) {  // refused: the gates stay on the prediction
    sh.bearing.value = sh.range.value = sh.clock.value = 0;
    sh.iterate = false;
  }
  return sh;
}

// Everything the passes need: the detections, the options and the reference series (for a
// rotation's rows, each evaluated at its own time).
struct Context {
  const std::vector<Detection>& det;
  const AssociationOptions& o;
  const PlaneSeries& observer;
  const std::map<std::string, PlaneSeries>& truth;
};

// The reference at t of one target (and the observer): false where either is not defined.
bool pred_at(const Context& c, const PlaneSeries& series, double t, Pred& pr) {
  double b = 0;
  if (!series.at(t, pr.p) || !series.velocity(t, c.o.velocity_half_span_s, pr.v) || !series.bridge(t, b, pr.interval_s)) return false;
  // the chord's miss a b / 2 (PlaneSeries::bridge)
  const double accel = c.o.reference_accel_mps2 < 0 ? series.accel_rms() : c.o.reference_accel_mps2;
  pr.interp_sd_m = 0.5 * accel * b;
  return true;
}

// The observer and the targets' predictions at the scan's time.
void set_geometry(const Context& c, const LocalLevelFrame& F, Scan& s) {
  if (!(c.observer.at(s.t, s.po) && c.observer.velocity(s.t, c.o.velocity_half_span_s, s.vo))) return;
  // gamma: the observer's local north, clockwise from the frame's north (meridian convergence,
  // about dlon sin(lat): 0.2 deg after 20 km east at 63 deg N). Bearings are measured from the
  // local north, so every vector is turned into the observer's local orientation.
  const Eigen::Vector3d north_F = F.from_ned(F.to_geodetic(Eigen::Vector3d(s.po.x(), 0.0, s.po.y())), Eigen::Vector3d::UnitX());
  s.gamma = std::atan2(north_F.z(), north_F.x());
  for (const auto& [name, series] : c.truth) {
    Pred pr{name, {}, {}};
    if (pred_at(c, series, s.t, pr)) s.preds.push_back(pr);
  }
}

// Per sensor: the rotation period if it stamps (nearly) every detection at a time of its own
// and its detections follow one rotating beam (rotation_scans.hpp); absent otherwise.
constexpr double kOwnStampFraction = 0.9;  // at least this share of its stamps hold one detection
std::map<std::string, RotationEstimate> rotating_sensors(const std::vector<Detection>& det) {
  struct Rows {
    std::vector<double> t, b;
    int stamps = 0, single = 0, in_stamp = 0;
    double last = NAN;
    bool ranged = false;
  };
  std::map<std::string, Rows> by;
  for (const Detection& x : det) {
    if (x.empty_scan()) continue;
    Rows& r = by[x.sensor];
    r.ranged = std::isfinite(x.range_m);
    if (x.t_s != r.last) {
      r.single += r.in_stamp == 1;
      ++r.stamps, r.in_stamp = 0, r.last = x.t_s;
    }
    ++r.in_stamp;
    r.t.push_back(x.t_s);
    r.b.push_back(x.bearing_rad);
  }
  std::map<std::string, RotationEstimate> out;
  for (auto& [sensor, r] : by) {
    r.single += r.in_stamp == 1;
    if (!r.ranged || r.stamps < kMinRotationDetections || r.single < kOwnStampFraction * r.stamps) continue;
    const RotationEstimate e = rotation_period(r.t, r.b);
    if (e.period_s > 0) out[sensor] = e;
  }
  return out;
}

// The scans of det, each with the observer and the targets' predictions at its time (frame F).
std::vector<Scan> make_scans(const Context& c, const LocalLevelFrame& F, const std::map<std::string, RotationEstimate>& rotating) {
  const auto& det = c.det;
  std::vector<Scan> scans;
  // scans: consecutive rows of one sensor with one t_s (sensors may interleave between scans)
  for (std::size_t i = 0; i < det.size();) {
    std::size_t j = i + 1;
    while (j < det.size() && det[j].sensor == det[i].sensor && det[j].t_s == det[i].t_s) ++j;
    if (rotating.count(det[i].sensor)) {
      i = j;
      continue;
    }
    Scan s;
    s.sensor = det[i].sensor;
    s.t = det[i].t_s;
    for (std::size_t k = i; k < j; ++k)
      if (!det[k].empty_scan()) s.rows.push_back(k), s.dt.push_back(0.0);
    s.ranged = !s.rows.empty() && std::isfinite(det[s.rows[0]].range_m);
    set_geometry(c, F, s);
    scans.push_back(std::move(s));
    i = j;
  }
  if (rotating.empty()) return scans;
  // a rotating sensor's rotations: k = floor((t - t_first) / P), each a scan at its middle
  for (const auto& [sensor, e] : rotating) {
    const double P = e.period_s;
    std::map<long, Scan> rot;
    double t_first = NAN;
    for (std::size_t k = 0; k < det.size(); ++k) {
      if (det[k].sensor != sensor || det[k].empty_scan()) continue;
      if (!std::isfinite(t_first)) t_first = det[k].t_s;
      const long n = static_cast<long>(std::floor((det[k].t_s - t_first) / P));
      Scan& s = rot[n];
      if (s.rows.empty()) s.sensor = sensor, s.t = t_first + (static_cast<double>(n) + 0.5) * P, s.ranged = true;
      s.rows.push_back(k);
      s.dt.push_back(det[k].t_s - s.t);
    }
    for (auto& [n, s] : rot) {
      set_geometry(c, F, s);
      scans.push_back(std::move(s));
    }
  }
  std::stable_sort(scans.begin(), scans.end(), [](const Scan& a, const Scan& b) { return a.t < b.t; });
  return scans;
}

// First pass: per sensor, the residuals of the unambiguous pairs inside the wide gates.
std::map<std::string, WideResiduals> wide_residuals(const std::vector<Scan>& scans, const std::vector<Detection>& det,
                                                    const AssociationOptions& o) {
  const double wide_b = std::max(o.wide_gate_bearing_deg, o.gate_bearing_deg) * kDegToRad;
  const double wide_m = std::max(o.wide_gate_position_m, o.gate_position_m);
  std::map<std::string, WideResiduals> wide;
  for (const Scan& s : scans) {
    WideResiduals& w = wide[s.sensor];
    w.ranged = w.ranged || s.ranged;
    const double gate = s.ranged ? wide_m : wide_b;
    for (std::size_t a = 0; a < s.preds.size(); ++a) {
      const Eigen::Vector2d da = s.preds[a].p - s.po;
      if (da.norm() < kMinPredRange) continue;
      bool crowded = false;  // another target's prediction within the wide gate
      for (std::size_t b = 0; b < s.preds.size(); ++b) crowded |= b != a && separation(s, da, s.preds[b].p - s.po) < gate;
      if (crowded) continue;
      int inside = 0;
      std::size_t hit = 0;
      for (std::size_t i = 0; i < s.rows.size(); ++i)
        if (distance(det[s.rows[i]], s, rel(s, i, s.preds[a])) <= gate) ++inside, hit = i;
      if (inside != 1) continue;
      bool shared = false;  // the detection inside another target's wide gate, too
      for (std::size_t b = 0; b < s.preds.size(); ++b)
        shared |= b != a && distance(det[s.rows[hit]], s, rel(s, hit, s.preds[b])) <= gate;
      if (shared) continue;
      const Eigen::Vector2d d = rel(s, hit, s.preds[a]), v = s.preds[a].v - s.vo;
      const Detection& dk = det[s.rows[hit]];
      PairResidual q;
      q.target = s.preds[a].target;
      q.bearing_rad = wrap_pi(dk.bearing_rad + s.gamma - bearing_rad(d));
      q.bearing_rate_radps = bearing_rate_radps(d, v);
      q.pred_range_m = d.norm();
      if (s.ranged) {
        q.range_m = dk.range_m - d.norm();
        q.range_rate_mps = range_jacobian(d) * v;
      }
      w.pairs.push_back(q);
    }
  }
  return wide;
}

// The residuals of a pass's associated pairs, per sensor and target.
std::map<std::string, WideResiduals> pass_residuals(const std::vector<AssociatedDetection>& out) {
  std::map<std::string, WideResiduals> r;
  for (const AssociatedDetection& x : out) {
    WideResiduals& w = r[x.sensor];
    w.ranged = w.ranged || x.has_range;
    PairResidual q;
    q.target = x.target;
    q.bearing_rad = wrap_pi(x.bearing_rad - x.bearing_pred());
    q.bearing_rate_radps = bearing_rate_radps(x.d, x.v_rel);
    q.pred_range_m = x.range_pred();
    if (x.has_range) {
      q.range_m = x.range_m - x.range_pred();
      q.range_rate_mps = x.drange() * x.v_rel;
    }
    w.pairs.push_back(q);
  }
  return r;
}

// The associated detection of target pr and row i of scan s: raw measurements and the reference
// geometry at the row's own time (never the shifted prediction). kNoReference where the
// reference is not defined there (a rotation's row beyond a gap), kOnObserver where the target is
// on top of the observer (no bearing: neither associated nor missed).
enum Outcome { kAssociated, kNoReference, kOnObserver };
Outcome associated(const Context& c, const Scan& s, std::size_t i, const Pred& pr, AssociatedDetection& x) {
  const Detection& dk = c.det[s.rows[i]];
  Pred at = pr;
  Eigen::Vector2d po = s.po, vo = s.vo;
  if (s.dt[i] != 0) {
    if (!(c.observer.at(dk.t_s, po) && c.observer.velocity(dk.t_s, c.o.velocity_half_span_s, vo) &&
          pred_at(c, c.truth.at(pr.target), dk.t_s, at)))
      return kNoReference;
  }
  const Eigen::Rotation2Dd to_local(-s.gamma);
  x.t_s = s.dt[i] != 0 ? dk.t_s : s.t;
  x.sensor = s.sensor;
  x.target = pr.target;
  x.has_range = s.ranged;
  x.bearing_rad = dk.bearing_rad;
  x.range_m = s.ranged ? dk.range_m : 0.0;
  x.d = to_local * (at.p - po);
  x.v_target = to_local * at.v;
  x.v_rel = to_local * (at.v - vo);
  const double speed = at.v.norm();
  x.u_course = speed > c.o.min_speed_mps ? Eigen::Vector2d(to_local * at.v / speed) : Eigen::Vector2d::Zero();
  x.ref_interp_sd_m = at.interp_sd_m;
  x.ref_interval_s = at.interval_s;
  return x.d.norm() >= kMinPredRange ? kAssociated : kOnObserver;
}

// Final pass over scan s: the unambiguous predictions' gates assigned detections one to one
// (assignment.hpp), appended to out.
void associate_scan(const Context& c, const Scan& s, const Shifts& shift, std::map<std::string, SensorAssociation>& stats,
                    std::vector<AssociatedDetection>& out) {
  const auto& det = c.det;
  const AssociationOptions& o = c.o;
  const double gate_b = o.gate_bearing_deg * kDegToRad;
  SensorAssociation& st = stats[s.sensor];
  ++st.scans;
  st.detections += static_cast<int>(s.rows.size());
  const auto sh = shift.find(s.sensor);
  const double db = sh == shift.end() ? 0.0 : sh->second.bearing.value, dr = sh == shift.end() ? 0.0 : sh->second.range.value;
  const double tau = sh == shift.end() ? 0.0 : sh->second.clock.value;
  const double gate = s.ranged ? o.gate_position_m : gate_b;
  const std::size_t T = s.preds.size();
  // ambiguity: two gating predictions within ambiguous_gates gates of each other
  std::vector<Eigen::Vector2d> gp;  // gating predictions relative to the observer, at the scan's time
  for (const auto& pr : s.preds) gp.push_back(shifted(pr.p - s.po - tau * (pr.v - s.vo), db, dr));
  std::vector<char> ambiguous(T, 0);
  for (std::size_t a = 0; a < T; ++a)
    for (std::size_t b = a + 1; b < T; ++b)
      if (separation(s, gp[a], gp[b]) < o.ambiguous_gates * gate) ambiguous[a] = ambiguous[b] = 1;
  if (std::any_of(ambiguous.begin(), ambiguous.end(), [](char x) { return x; })) ++st.ambiguous_scans;
  // cost (distance / gate)^2 inside the gate, a miss 1
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(T), static_cast<Eigen::Index>(s.rows.size()),
                                                   std::numeric_limits<double>::infinity());
  for (std::size_t a = 0; a < T; ++a) {
    if (ambiguous[a]) continue;
    for (std::size_t i = 0; i < s.rows.size(); ++i) {
      const double x = distance(det[s.rows[i]], s, shifted(rel(s, i, s.preds[a], tau), db, dr)) / gate;
      if (x <= 1) cost(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(i)) = x * x;
    }
  }
  const std::vector<long> col = assign_min_cost(cost, std::vector<double>(T, 1.0));
  for (std::size_t a = 0; a < T; ++a) {
    const Pred& pr = s.preds[a];
    if (ambiguous[a]) {
      ++st.ambiguous[pr.target];
      continue;
    }
    AssociatedDetection x;
    const Outcome got = col[a] < 0 ? kNoReference : associated(c, s, static_cast<std::size_t>(col[a]), pr, x);
    if (got == kOnObserver) continue;
    if (got == kNoReference) {
      ++st.missed[pr.target];
      continue;
    }
    out.push_back(x);
    ++st.associated[x.target];
  }
}

// One pass over every scan with the given shifts; stats of this pass alone into `stats`.
std::vector<AssociatedDetection> associate_all(const Context& c, const std::vector<Scan>& scans, const Shifts& shift,
                                               std::map<std::string, SensorAssociation>& stats) {
  std::vector<AssociatedDetection> out;
  for (const Scan& s : scans) associate_scan(c, s, shift, stats, out);
  return out;
}

// The shifts' record in a sensor's stats.
void record_shift(SensorAssociation& st, const SensorShift& sh, int wide_pairs) {
  st.gate_shift_bearing_rad = sh.bearing.value;
  st.gate_shift_range_m = sh.range.value;
  st.gate_shift_bearing_se_rad = sh.bearing.se;
  st.gate_shift_range_se_m = sh.range.se;
  st.gate_shift_clock_s = sh.clock.value;
  st.gate_shift_clock_se_s = sh.clock.se;
  st.clock_refused = sh.clock_refused;
  st.clock_refused_s = sh.clock_fitted_s;
  st.shift_refused = sh.refused;
  st.wide_pairs = wide_pairs;
  st.shift_rule = sh.across_targets ? "targets" : "pairs";
  st.shift_targets = sh.targets;
}

// A shift moved by more than kConvergedSe of its standard error (0 and 0: unmoved).
constexpr double kConvergedSe = 0.1;
bool moved(const ShiftEstimate& a, const ShiftEstimate& b) {
  if (a.value == b.value) return false;
  return std::abs(a.value - b.value) > kConvergedSe * std::max(b.se, 1e-300);
}

// [s] The first and last time of a detection (empty scans' rows left out); (inf, -inf) for none.
std::pair<double, double> detections_span(const std::vector<Detection>& det) {
  double t0 = INFINITY, t1 = -INFINITY;
  for (const Detection& x : det)
    if (!x.empty_scan()) t0 = std::min(t0, x.t_s), t1 = std::max(t1, x.t_s);
  return {t0, t1};
}

// A target whose reference covers only part of the detections' span is still there where it
// does not: its echoes would be taken for another target's or for clutter, and a gate fitted on
// such pairs moves off (Autoferry scenario 4 with Havfruen's reference cut at mid-span moved the
// lidar's gates by 40 deg). So every scan inside a stretch some target's reference does not cover
// (it starts late, ends early, or has a gap beyond reference_max_gap_s), longer than that gap, is
// left out for every target, and the stretch is named in the report (`reference`). Stretches of
// the raw reference count (a jump's cut stretch is the reference jump check's; the target was
// referenced there).
std::vector<Scan> leave_out_uncovered(std::vector<Scan> scans, const MultiSensorData& data, const AssociationOptions& o,
                                      std::map<std::string, ReferenceIntegrity>* reference) {
  const auto [t0, t1] = detections_span(data.detections);
  if (!(t1 > t0)) return scans;
  const double gap = o.reference_max_gap_s;
  std::map<std::string, std::vector<std::pair<double, double>>> uncovered;
  for (const auto& [name, v] : data.truth) {
    std::vector<std::pair<double, double>> u;
    double covered_to = t0;  // the detections' span is covered up to here
    for (std::size_t i = 0; i < v.size(); ++i) {
      const double t = v[i].t_s;
      if (i == 0 ? t - t0 > gap : t - v[i - 1].t_s > gap) {
        const double from = std::max(t0, i == 0 ? t0 : v[i - 1].t_s), to = std::min(t1, t);
        if (to - from > gap) u.push_back({from, to});
      }
      covered_to = t;
    }
    if (v.empty() || t1 - covered_to > gap) u.push_back({v.empty() ? t0 : std::max(t0, covered_to), t1});
    if (!u.empty()) uncovered[name] = u;
  }
  if (uncovered.empty()) return scans;
  std::vector<Scan> kept;
  std::map<std::string, std::pair<std::size_t, std::size_t>> left;  // per target: scans, detections
  for (Scan& sc : scans) {
    bool out = false;
    for (const auto& [name, u] : uncovered)
      for (const auto& [a, b] : u)
        if (sc.t >= a && sc.t <= b) {
          out = true;
          ++left[name].first, left[name].second += sc.rows.size();
          break;
        }
    if (!out) kept.push_back(std::move(sc));
  }
  if (reference)
    for (const auto& [name, u] : uncovered) {
      ReferenceIntegrity& ri = (*reference)[name];
      if (ri.jumps.empty()) ri.first_s = data.truth.at(name).empty() ? t0 : data.truth.at(name).front().t_s;
      ri.uncovered = u;
      ri.scans_left_out = left[name].first, ri.detections_left_out = left[name].second;
      ri.detections_from_s = t0, ri.detections_to_s = t1;
    }
  return kept;
}

// The references' time shift that best explains the range sensors' geometry, as a clause for the
// unit check's error ("" when none does). Shift delta: the references' stamps are delta late,
// their samples moved to t - delta. Scored by the target scans whose range ratio (range_ratios)
// lies within kShiftRatioTol of 1, over a grid of delta within +-kShiftSpanShare of the detections'
// span (at most kShiftSteps steps, at least 1 s), then refined tenfold around the best by the
// truncated log-ratio cost (Score::cost).
constexpr double kShiftRatioTol = 0.05, kShiftSpanShare = 0.75;
constexpr int kShiftSteps = 300;
std::string reference_time_shift_hint(const MultiSensorData& data, const std::map<std::string, std::vector<GeoSample>>& level,
                                      const LocalLevelFrame& F, const AssociationOptions& o,
                                      const std::map<std::string, RotationEstimate>& rotating) {
  const auto [t0, t1] = detections_span(data.detections);
  if (!(t1 > t0)) return "";
  const PlaneSeries observer(data.observer, F);
  struct Score {
    int good = 0, n = 0;
    double median = 0;
    double cost = 0;  ///< mean over the target scans of min(|log q|, log(1 + tol)): smooth where good is flat
  };
  auto score = [&](double delta) {
    // the shifted samples outlive the series over them (a PlaneSeries keeps a reference)
    std::map<std::string, std::vector<GeoSample>> moved = level;
    std::map<std::string, PlaneSeries> truth;
    for (auto& [name, w] : moved) {
      for (GeoSample& g : w) g.t_s -= delta;
      truth.emplace(name, PlaneSeries(w, F, o.reference_max_gap_s));
    }
    const Context c{data.detections, o, observer, truth};
    Score sc;
    std::vector<double> all;
    for (const auto& [sensor, r] : range_ratios(make_scans(c, F, rotating), data.detections))
      for (double q : r) {
        all.push_back(q);
        sc.good += std::abs(q - 1) <= kShiftRatioTol;
        sc.cost += std::min(std::abs(std::log(q)), std::log1p(kShiftRatioTol));
      }
    sc.n = static_cast<int>(all.size());
    sc.median = all.empty() ? 0 : median(all);
    sc.cost = all.empty() ? INFINITY : sc.cost / static_cast<double>(all.size());
    return sc;
  };
  const double half = kShiftSpanShare * (t1 - t0), step = std::max(1.0, 2 * half / kShiftSteps);
  double best = 0;
  Score best_score = score(0);
  const Score at_zero = best_score;
  for (double d = -half; d <= half; d += step) {
    const Score sc = score(d);
    if (sc.good > best_score.good) best = d, best_score = sc;
  }
  // refined tenfold around the best: within a ratio tolerance the count is flat over a second or
  // so, the truncated cost is not; among shifts keeping 90 % of the best count, the least cost
  const Score coarse = best_score;
  for (double d = best - step; d <= best + step; d += step / 10) {
    const Score sc = score(d);
    if (sc.good >= 0.9 * coarse.good && sc.cost < best_score.cost) best = d, best_score = sc;
  }
  if (best == 0 || best_score.good < kMinUnitSamples || best_score.good < 2 * at_zero.good ||
      std::abs(best_score.median - 1) > kShiftRatioTol)
    return "";
  return "; a time shift explains it: with truth.csv's times moved by " + short_num(-best) + " s (the references " +
         short_num(std::abs(best)) + " s " + (best > 0 ? "late" : "early") + " against detections.csv), the range sensors' " +
         "median ratio is " + short_num(best_score.median) + ", " + std::to_string(best_score.good) + " of " +
         std::to_string(best_score.n) + " target scans within " + short_num(100 * kShiftRatioTol) + " % of 1 (" +
         std::to_string(at_zero.good) + " of " + std::to_string(at_zero.n) + " as stamped)";
}

// References far from the observer, as a clause for the unit check's error ("" when they are
// not): every target's median predicted range over the scans (the nearest target's) beyond
// kFarRangeFactor times the farthest range any range sensor detects, clutter included (land
// returns reach a radar's instrumented range). A unit by 1000 or 1852 is named by the unit check
// before this; a camera may see a boat beyond a short-range lidar, but not twenty times beyond
// every echo of every range sensor.
constexpr double kFarRangeFactor = 20;
std::string reference_distance_hint(const std::vector<Scan>& scans, const std::vector<Detection>& det) {
  double farthest = 0;
  for (const Detection& x : det)
    if (!x.empty_scan() && std::isfinite(x.range_m)) farthest = std::max(farthest, x.range_m);
  std::map<std::string, std::vector<double>> pred;
  for (const Scan& s : scans)
    for (const auto& pr : s.preds) pred[pr.target].push_back((pr.p - s.po).norm());
  if (!(farthest > 0) || pred.empty()) return "";
  std::string nearest;
  double nearest_m = INFINITY;
  for (auto& [target, r] : pred) {
    const double m = median(r);
    if (m < nearest_m) nearest_m = m, nearest = target;
  }
  if (!(nearest_m > kFarRangeFactor * farthest)) return "";
  return "; the references lie far from the observer: the nearest target (" + nearest + ") at a median " +
         short_num(nearest_m / 1000) + " km, while no range sensor detects anything beyond " + short_num(farthest / 1000) +
         " km: observer.csv and truth.csv may be of different places, or one file's positions shifted";
}

// Sensors whose bearings point from the targets to the observer, as a clause for an error ("" for
// none): per sensor, the target scans with a detection within the gate of the target's reference
// bearing, and those with one within the gate of that bearing + 180 deg that no other target of
// the scan explains within kUnitsBearingDeg (a target on the far side at the same range is no
// evidence, even seen through a bias beyond the gate); a range sensor's within
// kReciprocalRangeTol of the target's range as well. kMinUnitSamples or more of the second kind,
// at least kReciprocalShare of the sensor's target scans (a sensor that sees its targets at all
// sees them in many scans; clutter at the far side now and then is no evidence) and
// kReciprocalFactor times the first: reciprocal. ranged_only: range sensors alone (their ranges
// make a coincidence with clutter unlikely).
constexpr double kReciprocalFactor = 3, kReciprocalRangeTol = 0.1, kReciprocalShare = 0.25;
std::string reciprocal_hint(const std::vector<Scan>& scans, const std::vector<Detection>& det, double gate_rad, bool ranged_only) {
  std::map<std::string, std::pair<int, int>> count;  // per sensor: (as given, turned by 180 deg)
  std::map<std::string, int> target_scans;
  for (const Scan& s : scans) {
    if (s.preds.empty() || s.rows.empty() || (ranged_only && !s.ranged)) continue;
    auto& [direct, turned] = count[s.sensor];
    // whether row i lies within the gate of target pr's prediction turned by `turn` [rad]
    auto near = [&](std::size_t i, const Pred& pr, double turn, double window) {
      const Detection& x = det[s.rows[i]];
      const Eigen::Vector2d rd = rel(s, i, pr);
      const bool range_ok = !s.ranged || std::abs(x.range_m / rd.norm() - 1) <= kReciprocalRangeTol;
      return range_ok && std::abs(wrap_pi(x.bearing_rad + s.gamma - bearing_rad(rd) - turn)) <= window;
    };
    for (const auto& pr : s.preds) {
      bool d = false, t = false;
      for (std::size_t i = 0; i < s.rows.size(); ++i) {
        d = d || near(i, pr, 0, gate_rad);
        if (t || !near(i, pr, M_PI, gate_rad)) continue;
        bool other = false;
        for (const auto& q : s.preds) other = other || (&q != &pr && near(i, q, 0, kUnitsBearingDeg * kDegToRad));
        t = !other;
      }
      direct += d, turned += t;
      ++target_scans[s.sensor];
    }
  }
  std::string out;
  for (const auto& [sensor, c] : count)
    if (c.second >= kMinUnitSamples && c.second >= kReciprocalFactor * c.first &&
        c.second >= kReciprocalShare * target_scans[sensor])
      out += "; detections.csv bearing_deg of sensor " + sensor + " looks like the reciprocal bearing, from the target to " +
             "the observer: " + std::to_string(c.second) + " of " + std::to_string(target_scans[sensor]) +
             " target scans have a detection at the target's bearing + 180 deg" +
             (ranged_only ? " and its range" : "") + ", " + std::to_string(c.first) + " at its bearing";
  return out;
}

}  // namespace

std::vector<AssociatedDetection> associate(const MultiSensorData& data, const AssociationOptions& o,
                                           std::map<std::string, SensorAssociation>& stats,
                                           std::map<std::string, ReferenceIntegrity>* reference) {
  check_options(o);
  if (data.truth.empty()) throw ConfigError("multi-sensor diagnosis: needs truth.csv (the targets' reference tracks)");
  // no target with a track: every reference a single sample (one target's single sample among
  // tracks leaves its detections unassociated, as a target seen once)
  if (std::all_of(data.truth.begin(), data.truth.end(), [](const auto& kv) { return kv.second.size() < 2; }))
    throw ConfigError("truth.csv: every target has a single sample (" + std::to_string(data.truth.size()) +
                      " targets); a reference track needs 2 or more");
  const LocalLevelFrame F(data.observer.front().g, 0.0);
  const PlaneSeries observer(data.observer, F);
  std::map<std::string, PlaneSeries> truth;
  auto level = data.truth_on_level();  // each target's reference, cut to its stretch without jumps
  if (o.reference_jump_accel_mps2 > 0) {
    ReferenceJumpOptions jo;
    jo.max_accel_mps2 = o.reference_jump_accel_mps2;
    jo.max_gap_s = o.reference_max_gap_s;
    for (auto& [name, v] : level) {
      const ReferenceIntegrity ri = check_reference_jumps(v, F, jo);
      if (ri.jumps.empty()) continue;
      if (reference) (*reference)[name] = ri;
      v = used_stretch(v, ri);
    }
  }
  for (const auto& [name, v] : level) truth.emplace(name, PlaneSeries(v, F, o.reference_max_gap_s));
  const Context c{data.detections, o, observer, truth};
  const std::map<std::string, RotationEstimate> rotating = rotating_sensors(data.detections);
  const std::vector<Scan> scans = leave_out_uncovered(make_scans(c, F, rotating), data, o, reference);

  // Ranges that match no unit: a reference late or early against the detections moves every
  // target along its track, and references of another place put every target far from the
  // observer; the ranges then miss the geometry though nothing is wrong with them. Say which.
  if (!data.simulated) {
    check_units(scans, data.detections, [&] {
      const std::string shift = reference_time_shift_hint(data, level, F, o, rotating);
      return shift.empty() ? reference_distance_hint(scans, data.detections) : shift;
    });
    // a range sensor whose echoes lie at the targets' ranges but opposite their bearings
    const std::string reciprocal = reciprocal_hint(scans, data.detections, o.gate_bearing_deg * kDegToRad, true);
    if (!reciprocal.empty()) throw ConfigError(reciprocal.substr(2));
    // ... and where too few target scans had a detection near a target's bearing for the unit
    // check to judge (seen from far away every target lies in one direction), the distance alone
    const std::string far = reference_distance_hint(scans, data.detections);
    if (!far.empty())
      throw ConfigError("truth.csv and observer.csv: no detection can be associated" + far +
                        " (the diagnosis would say only that no detection is associated to any target)");
  }

  // first pass (recentre_gates): unambiguous pairs inside the wide gates, and each sensor's shifts
  Shifts shift;
  std::map<std::string, int> wide_pairs;
  if (o.recentre_gates)
    for (const auto& [sensor, w] : wide_residuals(scans, data.detections, o)) {
      shift[sensor] = sensor_shift(w, o, true);
      wide_pairs[sensor] = static_cast<int>(w.pairs.size());
    }

  // the passes: gates around the predictions moved by each sensor's shifts (for gating only);
  // sensors whose shifts are judged across targets re-estimate them from the pairs associated
  std::map<std::string, SensorAssociation> st;
  std::vector<AssociatedDetection> out = associate_all(c, scans, shift, st);
  int passes = 1;
  const bool iterate = std::any_of(shift.begin(), shift.end(), [](const auto& x) { return x.second.iterate; });
  while (iterate && passes < o.max_passes) {
    bool any_moved = false;
    for (auto& [sensor, w] : pass_residuals(out)) {
      auto it = shift.find(sensor);
      if (it == shift.end() || !it->second.iterate) continue;
      const SensorShift next = sensor_shift(w, o, false);
      // too few targets left for the rule across them, too few pairs for a fit, or a shift beyond
      // the sensor's bounds: keep the shifts
      if (next.across_targets != it->second.across_targets || !next.iterate || !next.refused.empty()) continue;
      any_moved |= moved(it->second.bearing, next.bearing) || moved(it->second.range, next.range) ||
                   moved(it->second.clock, next.clock);
      it->second = next;
    }
    if (!any_moved) break;
    st.clear();
    out = associate_all(c, scans, shift, st);
    ++passes;
  }
  for (auto& [sensor, x] : st) {
    if (rotating.count(sensor)) {
      x.rotation_period_s = rotating.at(sensor).period_s;
      x.rotation_direction = rotating.at(sensor).direction;
    }
    const auto it = shift.find(sensor);
    if (it != shift.end()) record_shift(x, it->second, wide_pairs[sensor]);
    x.passes = it != shift.end() && it->second.iterate ? passes : 1;
    stats[sensor] = x;
  }
  // Nothing to diagnose: say why where the references or the bearings explain it (the diagnosis
  // would say only that no pair has detections enough)
  if (!data.simulated) {
    std::map<std::pair<std::string, std::string>, int> pairs;
    int most = 0;
    for (const auto& x : out) most = std::max(most, ++pairs[{x.sensor, x.target}]);
    if (most < kMinPairDetections) {
      std::string why = reciprocal_hint(scans, data.detections, o.gate_bearing_deg * kDegToRad, false);
      if (why.empty()) why = reference_time_shift_hint(data, level, F, o, rotating);
      if (why.empty()) why = reference_distance_hint(scans, data.detections);
      if (!why.empty())
        throw ConfigError("multi diagnosis: no sensor:target pair with " + std::to_string(kMinPairDetections) +
                          " or more associated detections (the most: " + std::to_string(most) + ")" + why);
    }
  }
  return out;
}

}  // namespace rnav
