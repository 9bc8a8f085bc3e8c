#include "multi_association.hpp"

#include "config.hpp"
#include "gross_check.hpp"
#include "plane_series.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

// One scan: rows [begin, end) of one sensor with one t_s, and the reference geometry at its time
// (frame F, (north, east)).
struct Scan {
  std::size_t begin = 0, end = 0;
  std::vector<std::size_t> rows;  // the rows with a detection
  bool ranged = false;
  Eigen::Vector2d po, vo;   // [m], [m/s] the observer's position and velocity
  double gamma = 0;         // [rad] the observer's local north, clockwise from the frame's north
  std::vector<Pred> preds;  // targets with a reference at t_s; empty without the observer's
};


// Distance of detection dk from prediction p (metres for range sensors, radians for bearing-only;
// its bearing turned into the frame).
double distance(const Detection& dk, const Scan& s, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = p - s.po;
  const double b_F = dk.bearing_rad + s.gamma;
  if (s.ranged) {
    const Eigen::Vector2d q = s.po + dk.range_m * Eigen::Vector2d(std::cos(b_F), std::sin(b_F));
    return (q - p).norm();
  }
  return std::abs(wrap_pi(b_F - bearing_rad(d)));
}

// Separation of two predictions, in the units of distance().
double separation(const Scan& s, const Eigen::Vector2d& pa, const Eigen::Vector2d& pb) {
  const Eigen::Vector2d da = pa - s.po, db = pb - s.po;
  return s.ranged ? (pa - pb).norm() : std::abs(wrap_pi(bearing_rad(da) - bearing_rad(db)));
}

// The prediction p moved by a bearing shift db [rad] and a range shift dr [m] about the observer:
//   d = p - p_O,  p' = p_O + max(0, |d| + dr) (cos(atan2(d_e, d_n) + db), sin(atan2(d_e, d_n) + db))
// p itself (bit for bit) without shift.
Eigen::Vector2d shifted(const Scan& s, const Eigen::Vector2d& p, double db, double dr) {
  if (db == 0 && dr == 0) return p;
  const Eigen::Vector2d d = p - s.po;
  const double b = bearing_rad(d) + db, r = std::max(0.0, d.norm() + dr);
  return s.po + r * Eigen::Vector2d(std::cos(b), std::sin(b));
}

// One sensor's unambiguous first-pass residuals.
struct WideResiduals {
  std::vector<double> bearing_rad;   // wrap(b_meas - b_pred) [rad]
  std::vector<double> range_m;       // r_meas - |d| [m], range sensors
  std::vector<double> pred_range_m;  // |d| [m], range sensors
};

// The shift a median of `r` earns: the median if there are `min_pairs`, beyond kShiftMinSe standard
// errors and, as `scale` x median, beyond kShiftMinGateFraction of `gate`; else 0.
double shift_of(const std::vector<double>& r, int min_pairs, double scale, double gate) {
  if (static_cast<int>(r.size()) < min_pairs) return 0;
  const double m = median(r);
  std::vector<double> dev(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) dev[i] = std::abs(r[i] - m);
  const double se = kMedianSeFactor * kMadToSigma * median(dev) / std::sqrt(static_cast<double>(r.size()));
  return std::abs(m) > kShiftMinSe * se && std::abs(m) * scale > kShiftMinGateFraction * gate ? m : 0.0;
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
void check_units(const std::vector<Scan>& scans, const std::vector<Detection>& det) {
  struct Acc {
    int bearings = 0, inside = 0, preds_outside = 0, preds = 0;
    std::vector<double> ratio;
  };
  std::map<std::string, Acc> acc;
  for (const Scan& s : scans) {
    if (s.preds.empty() || s.rows.empty()) continue;
    Acc& a = acc[det[s.begin].sensor];
    for (const auto& pr : s.preds) {
      ++a.preds;
      a.preds_outside += outside_radians_band(wrap_pi(bearing_rad(pr.p - s.po) - s.gamma));
    }
    for (auto k : s.rows) {
      ++a.bearings;
      if (std::abs(det[k].bearing_rad) <= kRadiansAsDegreesRad) ++a.inside;
    }
    if (!s.ranged) continue;
    // per target: of the detections within kUnitsBearingDeg of its bearing, the ratio nearest 1
    // (clutter at other ranges on its bearing, a shore or a wake, does not count)
    for (const auto& pr : s.preds) {
      const Eigen::Vector2d d = pr.p - s.po;
      if (d.norm() < kMinPredRange) continue;
      double best = INFINITY, q = 0;
      for (auto k : s.rows) {
        if (std::abs(wrap_pi(det[k].bearing_rad + s.gamma - bearing_rad(d))) > kUnitsBearingDeg * kDegToRad) continue;
        const double r = det[k].range_m / d.norm();
        if (r > 0 && std::abs(std::log(r)) < best) best = std::abs(std::log(r)), q = r;
      }
      if (q > 0) a.ratio.push_back(q);
    }
  }
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
                      std::to_string(a.ratio.size()) + " target scans (expected 1; a range off by more than 25 % is no sensor effect)");
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
  }
}

// The scans of det, each with the observer and the targets' predictions at its time (frame F).
std::vector<Scan> make_scans(const std::vector<Detection>& det, const AssociationOptions& o, const LocalLevelFrame& F,
                             const PlaneSeries& observer, const std::map<std::string, PlaneSeries>& truth) {
  const double h = o.velocity_half_span_s;
  // scans: consecutive rows of one sensor with one t_s (sensors may interleave between scans)
  std::vector<Scan> scans;
  for (std::size_t i = 0; i < det.size();) {
    std::size_t j = i + 1;
    while (j < det.size() && det[j].sensor == det[i].sensor && det[j].t_s == det[i].t_s) ++j;
    Scan s;
    s.begin = i;
    s.end = j;
    const double t = det[i].t_s;
    for (std::size_t k = i; k < j; ++k)
      if (!det[k].empty_scan()) s.rows.push_back(k);
    s.ranged = !s.rows.empty() && std::isfinite(det[s.rows[0]].range_m);
    // gamma: the observer's local north, clockwise from the frame's north (meridian convergence,
    // about dlon sin(lat): 0.2 deg after 20 km east at 63 deg N). Bearings are measured from the
    // local north, so every vector is turned into the observer's local orientation.
    if (observer.at(t, s.po) && observer.velocity(t, h, s.vo)) {
      const Eigen::Vector3d north_F =
          F.from_ned(F.to_geodetic(Eigen::Vector3d(s.po.x(), 0.0, s.po.y())), Eigen::Vector3d::UnitX());
      s.gamma = std::atan2(north_F.z(), north_F.x());
      for (const auto& [name, series] : truth) {
        Pred pr{name, {}, {}};
        double b = 0;
        if (!series.at(t, pr.p) || !series.velocity(t, h, pr.v) || !series.bridge(t, b, pr.interval_s)) continue;
        // the chord's miss a b / 2 (PlaneSeries::bridge)
        const double accel = o.reference_accel_mps2 < 0 ? series.accel_rms() : o.reference_accel_mps2;
        pr.interp_sd_m = 0.5 * accel * b;
        s.preds.push_back(pr);
      }
    }
    scans.push_back(std::move(s));
    i = j;
  }
  return scans;
}

using Shifts = std::map<std::string, std::pair<double, double>>;  // per sensor: (bearing [rad], range [m])

// First pass: per sensor, the residuals of the unambiguous pairs inside the wide gates.
std::map<std::string, WideResiduals> wide_residuals(const std::vector<Scan>& scans, const std::vector<Detection>& det,
                                                    const AssociationOptions& o) {
  const double wide_b = std::max(o.wide_gate_bearing_deg, o.gate_bearing_deg) * kDegToRad;
  const double wide_m = std::max(o.wide_gate_position_m, o.gate_position_m);
  std::map<std::string, WideResiduals> wide;
  for (const Scan& s : scans) {
    WideResiduals& w = wide[det[s.begin].sensor];
    const double gate = s.ranged ? wide_m : wide_b;
    for (std::size_t a = 0; a < s.preds.size(); ++a) {
      const Eigen::Vector2d& pa = s.preds[a].p;
      const Eigen::Vector2d d = pa - s.po;
      if (d.norm() < kMinPredRange) continue;
      bool crowded = false;  // another target's prediction within the wide gate
      for (std::size_t b = 0; b < s.preds.size(); ++b) crowded |= b != a && separation(s, pa, s.preds[b].p) < gate;
      if (crowded) continue;
      int inside = 0;
      std::size_t hit = 0;
      for (auto k : s.rows)
        if (distance(det[k], s, pa) <= gate) ++inside, hit = k;
      if (inside != 1) continue;
      bool shared = false;  // the detection inside another target's wide gate, too
      for (std::size_t b = 0; b < s.preds.size(); ++b)
        shared |= b != a && distance(det[hit], s, s.preds[b].p) <= gate;
      if (shared) continue;
      w.bearing_rad.push_back(wrap_pi(det[hit].bearing_rad + s.gamma - bearing_rad(d)));
      if (s.ranged) {
        w.range_m.push_back(det[hit].range_m - d.norm());
        w.pred_range_m.push_back(d.norm());
      }
    }
  }
  return wide;
}

// Each sensor's gate shifts from its first-pass residuals, recorded in its stats too.
Shifts gate_shifts(const std::vector<Scan>& scans, const std::vector<Detection>& det, const AssociationOptions& o,
                   std::map<std::string, SensorAssociation>& stats) {
  const double gate_b = o.gate_bearing_deg * kDegToRad;
  Shifts shift;
  for (const auto& [sensor, w] : wide_residuals(scans, det, o)) {
    const bool ranged = !w.range_m.empty();
    // a range sensor's bearing shift is judged as metres across the line of sight at the pairs' median range
    const double scale = ranged ? median(w.pred_range_m) : 1.0;  // [m/rad] or [1]
    const double db = shift_of(w.bearing_rad, o.recentre_min_pairs, scale, ranged ? o.gate_position_m : gate_b);
    const double dr = ranged ? shift_of(w.range_m, o.recentre_min_pairs, 1.0, o.gate_position_m) : 0.0;
    shift[sensor] = {db, dr};
    SensorAssociation& st = stats[sensor];
    st.gate_shift_bearing_rad = db;
    st.gate_shift_range_m = dr;
    st.wide_pairs = static_cast<int>(w.bearing_rad.size());
  }
  return shift;
}

// Final pass over scan s: each unambiguous prediction's nearest detection inside its gate, appended to out.
void associate_scan(const Scan& s, const std::vector<Detection>& det, const AssociationOptions& o, const Shifts& shift,
                    std::map<std::string, SensorAssociation>& stats, std::vector<AssociatedDetection>& out) {
  const double gate_b = o.gate_bearing_deg * kDegToRad;
  const std::string& sensor = det[s.begin].sensor;
  const double t = det[s.begin].t_s;
  SensorAssociation& st = stats[sensor];
  ++st.scans;
  st.detections += static_cast<int>(s.rows.size());
  const auto sh = shift.find(sensor);
  std::vector<Eigen::Vector2d> gp;  // gating predictions
  for (const auto& pr : s.preds)
    gp.push_back(sh == shift.end() ? pr.p : shifted(s, pr.p, sh->second.first, sh->second.second));
  const Eigen::Rotation2Dd to_local(-s.gamma);
  auto dist = [&](std::size_t k, const Eigen::Vector2d& p) { return distance(det[k], s, p); };
  const double gate = s.ranged ? o.gate_position_m : gate_b;
  // ambiguity: two predictions within one gate of each other
  std::vector<char> ambiguous(s.preds.size(), 0);
  for (std::size_t a = 0; a < s.preds.size(); ++a)
    for (std::size_t b = a + 1; b < s.preds.size(); ++b)
      if (separation(s, gp[a], gp[b]) < 2 * gate) ambiguous[a] = ambiguous[b] = 1;
  if (std::any_of(ambiguous.begin(), ambiguous.end(), [](char c) { return c; })) ++st.ambiguous_scans;
  std::vector<long> claim(s.preds.size(), -1);
  for (std::size_t a = 0; a < s.preds.size(); ++a) {
    if (ambiguous[a]) continue;
    double best = std::numeric_limits<double>::infinity();
    for (auto k : s.rows)
      if (dist(k, gp[a]) < best) best = dist(k, gp[a]), claim[a] = static_cast<long>(k);
    if (!(best <= gate)) claim[a] = -1;
  }
  for (std::size_t a = 0; a < s.preds.size(); ++a) {
    if (ambiguous[a]) continue;
    bool lost = claim[a] < 0;
    for (std::size_t b = 0; b < s.preds.size() && !lost; ++b)
      if (b != a && claim[b] == claim[a] &&
          dist(static_cast<std::size_t>(claim[a]), gp[b]) < dist(static_cast<std::size_t>(claim[a]), gp[a]))
        lost = true;
    if (lost) {
      ++st.missed[s.preds[a].target];
      continue;
    }
    const Pred& pr = s.preds[a];
    const Detection& dk = det[static_cast<std::size_t>(claim[a])];
    AssociatedDetection x;  // raw measurements and reference geometry (never the shifted prediction)
    x.t_s = t;
    x.sensor = sensor;
    x.target = pr.target;
    x.has_range = s.ranged;
    x.bearing_rad = dk.bearing_rad;
    x.range_m = s.ranged ? dk.range_m : 0.0;
    x.d = to_local * (pr.p - s.po);
    x.v_target = to_local * pr.v;
    x.v_rel = to_local * (pr.v - s.vo);
    const double speed = pr.v.norm();
    x.u_course = speed > o.min_speed_mps ? Eigen::Vector2d(to_local * pr.v / speed) : Eigen::Vector2d::Zero();
    x.ref_interp_sd_m = pr.interp_sd_m;
    x.ref_interval_s = pr.interval_s;
    if (x.d.norm() < kMinPredRange) continue;  // on top of the observer: no bearing
    out.push_back(x);
    ++st.associated[x.target];
  }
}

}  // namespace

std::vector<AssociatedDetection> associate(const MultiSensorData& data, const AssociationOptions& o,
                                           std::map<std::string, SensorAssociation>& stats,
                                           std::map<std::string, ReferenceIntegrity>* reference) {
  check_options(o);
  if (data.truth.empty()) throw ConfigError("multi-sensor diagnosis: needs truth.csv (the targets' reference tracks)");
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
  const auto& det = data.detections;
  const std::vector<Scan> scans = make_scans(det, o, F, observer, truth);

  check_units(scans, det);

  // first pass (recentre_gates): unambiguous pairs inside the wide gates, and each sensor's shifts
  Shifts shift;  // per sensor: (bearing [rad], range [m])
  if (o.recentre_gates) shift = gate_shifts(scans, det, o, stats);

  // final pass: the gates around the predictions, moved by the sensor's shifts for gating only
  std::vector<AssociatedDetection> out;
  for (const Scan& s : scans) associate_scan(s, det, o, shift, stats, out);
  return out;
}

}  // namespace rnav
