// Association of multi-sensor detections to the targets' reference tracks (truth), and the
// geometry every diagnosis column needs.
//
// Frame: local level at the first observer sample, 2-D (north, east) [m]; each associated
// detection's vectors (d, v_rel, v_target, u_course) are turned into the observer's own local
// orientation at its time (bearings are measured from the local north, which turns by
// dlon sin(lat) as the observer moves: 0.2 deg after 20 km east at 63 deg N). Per scan (one sensor,
// one t_s) and target with a reference position p_T(t) (linear interpolation, no gap longer than
// AssociationOptions::reference_max_gap_s; a reference without heights taken at the frame's level):
// predicted relative position d = p_T - p_O; the detection nearest to it is the target's if
// within the gate (range sensors: distance between the detection's position and p_T; bearing-only
// sensors: bearing difference). A scan where two targets' predictions are within one gate of
// each other is ambiguous for both and left out; a detection claimed by two targets goes to the
// nearer. Clutter (detections of nothing) and missed detections are normal.
//
// Gates recentred on each sensor's common bias (AssociationOptions::recentre_gates): a sensor
// whose bearings (or ranges) are off would otherwise be associated through gates centred on the
// unbiased prediction. Beyond the gate it associates nearly nothing (a 5 deg bearing bias is
// 26 m at 300 m, beyond a 20 m gate); inside it, the gate keeps mostly the detections whose
// error happens to be small, and in a busy picture whatever return lies nearest the unbiased
// prediction (another ship, a buoy, clutter), so the bias comes out pulled towards zero. A
// first pass with wide gates takes only unambiguous pairs (exactly one detection inside a
// target's wide gate, that detection inside no other target's wide gate, and no other target's
// prediction within the wide gate); per sensor and target the medians of
//   bearing residual  wrap(b_meas - b_pred)   [rad]
//   range residual    r_meas - |d|            [m] (range sensors)
// A common shift is judged in one of two ways:
//  * across targets (at least kMinCommonTargets targets with kMinTargetPairs pairs each): the
//    median m of the targets' medians, with the standard error of a median over targets
//    se = sqrt(pi/2) 1.4826 MAD(target medians) / sqrt(J); applied when |m| > 3 se (a bias every
//    target shares, whatever its size against the gate: per-target offsets - hulls seen away from
//    their antennas, a reference's own clock - scatter the targets' medians and raise se). The
//    association then iterates: associate with the gates around the prediction moved by the
//    shifts, re-estimate the shifts from the pairs associated (gates centred on the corrected
//    prediction truncate symmetrically), until no shift moves by more than a tenth of its se, or
//    max_passes;
//  * on pairs (fewer targets, as on the Autoferry recordings' two or three boats, whose
//    per-target offsets cannot be told from a common one): the sensor's bearing bias b, range
//    bias r (range sensors) and clock tau (stamp minus true time) fitted jointly on all
//    unambiguous pairs,
//      bearing residual = b - beta_dot tau,   range residual = r - r_dot tau
//    (beta_dot, r_dot: the rates of the predicted bearing and range along the relative
//    velocity), by Huber's robust M-estimate with each quantity's MAD scale, standard errors from
//    its sandwich covariance; the clock kept only beyond 3 of its SEs (else b and r refitted
//    alone), each term applied only beyond 3 SEs, and all only with n >= recentre_min_pairs and
//    when they move the median pair's prediction beyond the final gate itself (a range sensor's
//    as metres): only a bias the gate would lose. A clock on boats whose bearings turn the same
//    way moves every residual by -beta_dot tau, so a median constant (the rule before) took the
//    bias plus the clock's share and left the gates off the data. An applied fit is then
//    refined like the shifts across targets, from the pairs each pass associates, until no term
//    moves by more than a tenth of its SE, or max_passes.
// The shifts move each prediction's bearing and range (and, by the clock, its time) for gating
// only: the associated measurements and geometry stay the raw ones, so the diagnosis estimates
// the bias itself from the raw residuals. Without an applied shift the final pass is exactly the
// one-pass association. Across targets a sensor's clock offset, which moves each target along
// its own velocity, is not fitted: a common shift takes up only its share at the targets' median.
//
// Assignment: in each scan the targets' gates are assigned detections jointly, one detection per
// target and one target per detection (assignment.hpp), minimising the sum of (distance /
// gate)^2 with a miss costing 1 (a gate's edge).
//
// A rotating radar that stamps each detection at its own illumination time (nearly every stamp
// holds one detection) is read as scans of one rotation each (rotation_scans.hpp); each
// detection's prediction is taken at its own time.
#pragma once

#include "estimators/diagnosis/multi_sensor_data.hpp"
#include "estimators/diagnosis/reference_jumps.hpp"

#include "common/physics/bearing.hpp"
#include <Eigen/Dense>

#include <map>
#include <string>
#include <vector>

namespace rnav {

struct AssociationOptions {
  double gate_bearing_deg = 3;    ///< [deg] gate of bearing-only sensors, (0, 45]
  double gate_position_m = 20;    ///< [m] gate of range sensors, > 0
  double velocity_half_span_s = 1;///< [s] half-span of the central differences for velocities, > 0
  double min_speed_mps = 0.5;     ///< [m/s] a target's course (for hull offsets) is defined above this speed
  /// [s] a reference track is interpolated (linearly) only between samples at most this far
  /// apart; a detection inside a longer gap is not associated, > 0. 2 s suits a GNSS reference
  /// at 1 Hz or faster; an AIS reference (a report every 2-10 s, 3 min at anchor) needs 10 s or more.
  double reference_max_gap_s = 2;
  /// [m/s^2] RMS per horizontal axis of a target's acceleration between its reference samples,
  /// behind the interpolation's own uncertainty (AssociatedDetection::ref_interp_sd_m): -1
  /// (default): each target's own, from its reference's second differences
  /// (PlaneSeries::accel_rms, an upper estimate); 0: the interpolated reference taken as exact;
  /// else this value for every target, >= 0.
  double reference_accel_mps2 = -1;
  /// [m/s^2] a reference sample further off the chord through its neighbours (about 0.25 s either
  /// side) than a target accelerating at this much could be, beyond the track's own scatter, is a
  /// jump of the reference (a GNSS fix changing), not of the target: each target's reference is
  /// used only on its longest stretch without jumps (reference_jumps.hpp), >= 0; 0: no check.
  double reference_jump_accel_mps2 = 5;
  /// Recentre each sensor's gates on its common bearing and range bias, estimated from a first
  /// pass with the wide gates below (see the file comment); false: the one-pass association.
  bool recentre_gates = true;
  /// [deg] first-pass gate of bearing-only sensors, (0, 90]; one below gate_bearing_deg is taken
  /// as gate_bearing_deg. 20 deg holds a bias of up to about 19 deg at 0.5 deg noise.
  double wide_gate_bearing_deg = 20;
  /// [m] first-pass gate of range sensors (distance between detection and prediction), > 0; one
  /// below gate_position_m is taken as gate_position_m. 200 m holds a 20 deg bearing bias at
  /// 500 m (174 m), or a range bias of up to about 190 m at a few metres of noise.
  double wide_gate_position_m = 200;
  /// Unambiguous first-pass pairs a sensor needs before its shifts are estimated, >= 3 (10 by
  /// default: a median that one or two clutter pairs cannot carry).
  int recentre_min_pairs = 10;
  /// Passes of the association with gates recentred across targets (see the file comment), >= 1.
  int max_passes = 6;
  /// Two targets whose predictions lie closer than this many gates in a scan are ambiguous there
  /// and both left out of it, > 0. 2 (the default) keeps each gate clear of the other target's
  /// (the one-to-one assignment then equals each target's nearest detection); 1 lets the
  /// assignment decide between targets one to two gates apart.
  double ambiguous_gates = 2;
};

/// A common gate shift is judged across targets when at least this many targets have
/// kMinTargetPairs pairs each (a median and MAD over targets need a handful; the Autoferry
/// recordings' two or three boats stay with the rule on pairs).
/// associated detections a sensor:target pair needs to be diagnosed (fewer: too few to identify
/// its noise; reported, not used)
constexpr int kMinPairDetections = 10;
constexpr int kMinCommonTargets = 5;
constexpr int kMinTargetPairs = 5;  ///< pairs a target needs for its median to count

/// One detection associated to a target, with its reference geometry.
struct AssociatedDetection {
  double t_s = 0;
  std::string sensor, target;
  bool has_range = false;
  double bearing_rad = 0;          ///< measured bearing, clockwise from north
  double range_m = 0;              ///< measured range (has_range)
  Eigen::Vector2d d;               ///< [m] reference target position minus observer (local north, east at the observer)
  Eigen::Vector2d v_rel;           ///< [m/s] its rate (target velocity minus observer velocity)
  Eigen::Vector2d v_target;        ///< [m/s] target velocity from its reference track
  Eigen::Vector2d u_course;        ///< unit vector along the target's course; zero below min_speed
  /// [m] sd per horizontal axis of the reference position's interpolation error at t_s: a track
  /// accelerating at a (AssociationOptions::reference_accel_mps2) leaves the chord between the
  /// samples t_a <= t_s <= t_b by a (t_s - t_a)(t_b - t_s) / 2; 0 at a sample.
  double ref_interp_sd_m = 0;
  double ref_interval_s = 0;       ///< [s] t_b - t_a: the reference interval around t_s
  double bearing_pred() const { return rnav::bearing_rad(d); }
  double range_pred() const { return d.norm(); }
  /// d bearing / d d [rad/m] and d range / d d [1], as rows (north, east).
  Eigen::RowVector2d dbearing() const { return bearing_jacobian(d); }
  Eigen::RowVector2d drange() const { return range_jacobian(d); }
};

struct SensorAssociation {
  int scans = 0, detections = 0, ambiguous_scans = 0;
  std::map<std::string, int> associated, missed;  ///< per target
  std::map<std::string, int> ambiguous;           ///< per target: scans where it was left out as ambiguous
  /// Gate recentring (AssociationOptions::recentre_gates): the shifts the final pass's predictions
  /// were moved by for gating, 0 where not applied (too few pairs, not significant, or off).
  double gate_shift_bearing_rad = 0;  ///< [rad] added to every predicted bearing, clockwise
  double gate_shift_range_m = 0;      ///< [m] added to every predicted range (range sensors)
  int wide_pairs = 0;                 ///< unambiguous first-pass pairs the shifts were estimated from
  /// "targets": the shifts are medians over targets (shift_targets of them), iterated; "pairs":
  /// a bias and clock fitted on pairs, applied only when they move the gates beyond the gate, then
  /// iterated; "" without recentring
  std::string shift_rule;
  int shift_targets = 0;              ///< targets whose medians gave the shifts ("targets" rule)
  double gate_shift_bearing_se_rad = 0;  ///< [rad] the bearing shift's standard error
  double gate_shift_range_se_m = 0;      ///< [m] the range shift's standard error
  /// [s] the sensor's clock (stamp minus true time) the gating predictions were moved back by
  /// along each target's relative velocity ("pairs" rule; 0 where not applied or across targets)
  double gate_shift_clock_s = 0;
  double gate_shift_clock_se_s = 0;      ///< [s] the clock's standard error ("pairs" rule)
  /// A clock significant on the pooled pairs but left out of the gates, and why (the targets'
  /// own clocks disagree, or only one target has a fit); "" when applied or not significant
  std::string clock_refused;
  double clock_refused_s = 0;            ///< [s] that clock's pooled value (0 when none refused)
  /// A fitted shift beyond what the sensor's kind can be off by (bearing-only: 15 deg, 5 s; range
  /// sensors: 10 deg, 100 m or a quarter of the pairs' median range, 5 s), refused - the gates stay
  /// on the prediction - and why; "" otherwise
  std::string shift_refused;
  int passes = 1;                     ///< association passes run (the last one's pairs are used)
  /// [s] > 0: the sensor stamps each detection at its own time and was read as scans of one
  /// rotation of this period each (rotation_scans.hpp); 0: scans as stamped
  double rotation_period_s = 0;
  int rotation_direction = 0;  ///< with a rotation period: +1 clockwise, -1 counter-clockwise; 0 otherwise
};

/// Associate every scan; stats per sensor; with `reference`, the jump check of each target whose
/// reference jumped (AssociationOptions::reference_jump_accel_mps2). Throws ConfigError without truth.
std::vector<AssociatedDetection> associate(const MultiSensorData& data, const AssociationOptions& o,
                                           std::map<std::string, SensorAssociation>& stats,
                                           std::map<std::string, ReferenceIntegrity>* reference = nullptr);

}  // namespace rnav
