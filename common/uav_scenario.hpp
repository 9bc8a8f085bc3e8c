// The azimuth-only scenario (method.md section 2): a UAV circling a surface object measures
// bearings to it and estimates its position and velocity. Every option with unit, default and
// range; strict parsing as in scenario.hpp. Frame F: local level at the origin, x north,
// z east, y up; bearings atan2(east, north), clockwise from north.
#pragma once

#include "config.hpp"
#include "frames.hpp"
#include "scenario.hpp"

#include <array>
#include <ostream>
#include <string>
#include <vector>

namespace rnav {

/// The surface object. Constant velocity unless manoeuvres are scripted.
struct TargetOptions {
  double start_north_m = 0;   ///< [m] first position from the origin
  double start_east_m = 0;    ///< [m]
  double speed_mps = 1.0;     ///< [m/s] initial speed, [0, 30]
  double heading_deg = 45;    ///< [deg] initial course, clockwise from north
  /// Manoeuvres, each [t_s, duration_s, turn_rate_dps, accel_mps2]: from t_s for duration_s the
  /// course changes at turn_rate_dps (deg/s, clockwise positive) and the speed at accel_mps2.
  std::vector<std::array<double, 4>> manoeuvres;
};

/// The UAV's path and guidance.
///  - guidance "orbit" (default): the prescribed ground track of `path` (today's paper figures):
///    a circle about the object's first position (+ offset) or a straight pass. Wind and the
///    turn limits do not apply (the track is flown exactly).
///  - guidance "los": line-of-sight guidance from the measured bearing (sim/uav/guidance.hpp):
///    the course is kept perpendicular to the last measured bearing (object on the left for
///    "ccw", on the right for "cw"), corrected towards radius_m by the estimator's range when it
///    has one (the estimate of `guidance_estimator`, estimate_latency_s old).
///  - guidance "estimate": an orbit of radius_m about the estimator's position estimate
///    (predicted to the current time with its velocity), estimate_latency_s old.
///  Closed loop (los, estimate): the UAV flies at airspeed speed_mps in the constant wind, its
///  turn rate limited by max_bank_deg and max_turn_rate_dps; it starts where the orbit would.
struct ObserverOptions {
  std::string path = "circle";   ///< "circle" (orbit) or "straight" (a pass by the object); guidance "orbit" only
  double radius_m = 300;         ///< [m] orbit radius / standoff range; straight: distance of closest approach, [20, 20000]
  double speed_mps = 20;         ///< [m/s] orbit: ground speed; los, estimate: airspeed, [1, 200]
  std::string guidance = "orbit";        ///< "orbit", "los" or "estimate" (see above)
  double max_bank_deg = 30;              ///< [deg] bank limit: turn rate <= g tan(bank) / airspeed, (0, 80]
  double max_turn_rate_dps = 20;         ///< [deg/s] turn-rate limit of the airframe, (0, 180]
  double heading_time_constant_s = 2;    ///< [s] heading loop: rate command = heading error / this (+ feed-forward), [0.1, 100]
  double standoff_gain = 1;              ///< range law: course offset atan(gain (r - radius) / radius) towards the object, [0, 10]
  double wind_north_mps = 0;             ///< [m/s] constant wind (air mass velocity), north, |w| < airspeed
  double wind_east_mps = 0;              ///< [m/s] constant wind, east
  double estimate_latency_s = 1;         ///< [s] age of the estimate guidance uses (estimator + link); runner.window_s <= this, [0.01, 100]
  std::string guidance_estimator = "rpekf";  ///< the estimator (UAV_TMA's `estimator`) whose estimate guidance uses
  double altitude_m = 150;       ///< [m] height above the origin's ellipsoidal height, [0, 5000]
  std::string direction = "ccw"; ///< orbit direction seen from above: "ccw" or "cw"
  double centre_offset_north_m = 0;  ///< [m] orbit centre (straight: point of closest approach) from the object's first position
  double centre_offset_east_m = 0;   ///< [m]
  double start_angle_deg = 180;  ///< [deg] circle: bearing from the centre to the UAV's start
  double straight_heading_deg = 90;  ///< [deg] straight: the UAV's course
};

/// The UAV's SNS/INS position error (horizontal, per axis) as used for the bearing's origin.
struct ObserverNavOptions {
  double white_sigma_m = 0.3;   ///< [m] white part, 1 sigma per axis
  double corr_sigma_m = 0.0;    ///< [m] time-correlated (Gauss-Markov) part, 1 sigma per axis
  double corr_tau_s = 60;       ///< [s] its correlation time
  double vel_sigma_mps = 0.05;  ///< [m/s] velocity error per axis, white
};

/// The passive sensor (TV/IR): bearings only.
struct SensorOptions {
  double sigma_deg = 0.5;       ///< [deg] bearing noise, 1 sigma, (0, 10]
  double period_s = 0.2;        ///< [s] frame period (5 Hz); also the truth step
  double fov_centre_deg = 0;    ///< [deg] centre of the field of regard relative to the UAV's course
  double fov_half_deg = 180;    ///< [deg] half-width of the field of regard (180: all round)
  double max_range_m = 10000;   ///< [m] no detection beyond this range
  double min_range_m = 1;       ///< [m] no detection closer than this horizontal range (nadir)
};

/// Further bearing error effects (the azimuth-only diagnosis catalogue), all off by default, so
/// tests and users can make data with a known hidden effect. Names match `scripts/diagnose uav`.
/// (target_maneuver is made with target.manoeuvres.)
struct SensorEffectsOptions {
  double bearing_bias_rad = 0;       ///< bearing_bias: constant error added to every bearing [rad], |b| <= 0.2
  double time_offset_s = 0;          ///< bearing_time_offset: sensor time stamp minus true time [s]: db = -beta_dot tau, |tau| <= 10
  double bias_drift_radps = 0;       ///< bias_drift: bearing error growing at this rate from t = 0 [rad/s]
  double noise_scale = 1;            ///< noise_scale: white-noise sigma multiplier, (0, 100]
  double correlated_noise_tau_s = 0; ///< correlated_noise: the noise as a Gauss-Markov process with this correlation time [s] (0: white)
  double outlier_prob = 0;           ///< outliers: probability per frame, [0, 0.5]
  double outlier_scale = 10;         ///< outliers: their sigma in units of the noise sigma, [1, 1000]
  double periodic_period_s = 0;      ///< periodic: period [s] (0: none)
  double periodic_amplitude_rad = 0; ///< periodic: amplitude [rad] of a sine in time
};

/// The azimuth-only estimators.
struct TmaOptions {
  /// [m^2/s^3] white-acceleration spectral density of the CV model. 0 (default) matches the
  /// default constant-velocity object; raise it for manoeuvring objects.
  double q_m2ps3 = 0;
  double range_prior_m = 600;   ///< [m] range prior at the first bearing (not the truth)
  double range_sigma_m = 400;   ///< [m] its 1 sigma
  double vel_sigma_mps = 2.0;   ///< [m/s] prior 1 sigma of each velocity component (mean 0)
  long bank_size = 8;           ///< RP-EKF: number of range-parameterised filters, [2, 64]
  double bank_min_m = 50;       ///< [m] RP-EKF: smallest range
  double bank_max_m = 3000;     ///< [m] RP-EKF: largest range
  bool add_nav_noise = true;    ///< bearing variance + (nav sigma / range)^2
  /// Particle filter "pf": number of particles M, [100, 1000000]. Its initial range is drawn
  /// log-uniform over [bank_min_m, bank_max_m]. Cost O(M) per bearing: the default run takes
  /// about 0.35 s per realization at 8000. With 4000 the default run's mean NEES left the 95 %
  /// band for one of three seeds (4.58 > 4.40, 200 runs); with 1000 it was 25.
  long pf_particles = 8000;
  /// The estimators the node runs and publishes, in this order (UAV_TMA's `estimator`):
  /// "ekf" (the paper's Cartesian EKF), "rpekf" (the range-parameterised bank), "ml" (the batch
  /// MAP estimator, tma_batch_ml.hpp), "pf" (the regularised particle filter, tma_particle.hpp).
  /// At least one, no repeats.
  std::vector<std::string> estimators{"ekf", "rpekf"};
  /// Every name `estimators` accepts.
  static const std::vector<std::string>& known_estimators();
};

struct UavLoggerOptions {
  double eval_time_s = -1;      ///< [s] when summary.json's figures are taken; -1: after two orbits
  double diverge_pos_m = 50;    ///< [m] a run whose position error at eval_time exceeds this diverged
  /// [s] realizations.csv has, per realization and estimator, the first frame in each interval
  /// [k step, (k+1) step) of run time (and the frame summary.json uses); 0: every frame.
  double realizations_step_s = 1;
  /// track.csv (loggers/uav_track.hpp; drawn as geometry.png): this realization's geometry frame
  /// by frame, >= 0 and below the run's realization count; -1: no track.csv.
  long track_realization = 0;
};
/// Throws ConfigError (naming logger.track_realization) unless it is -1 or below n_realizations.
void check_track_realization(const UavLoggerOptions& o, long n_realizations);

struct UavScenario {
  std::string name = "uav";
  Geodetic origin{63.4389, 10.3950, 0.0};  ///< frame F's origin (default: Trondheim harbour, sea level)
  double duration_s = -1;       ///< [s] sim time; -1: two orbit periods (2 * 2 pi R / V)
  TargetOptions target;
  ObserverOptions uav;
  ObserverNavOptions uav_nav;
  SensorOptions sensor;
  SensorEffectsOptions sensor_effects;
  TmaOptions tma;
  UavLoggerOptions logger;
  RunnerOptions runner;

  static UavScenario load(const std::string& file, const std::vector<std::string>& overrides = {});
  static UavScenario from_json(const nlohmann::json& doc);
  void print(std::ostream& os) const;

  /// Frame F (x north, z east, y up) at the origin.
  LocalLevelFrame frame() const { return LocalLevelFrame(origin, 0.0); }
  /// The UAV's guidance uses the estimator's output (UAV_TMA), i.e. guidance is "los" or "estimate".
  bool closed_loop() const { return uav.guidance != "orbit"; }
  /// [s] one orbit: 2 pi R / V.
  double orbit_period_s() const;
  /// [s] the summary's evaluation time.
  double eval_time_s() const;
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }
  /// The lock-step nodes a multi-process run starts, each the process rnav_<name>: target, uav,
  /// uav_tma, uav_logger (scripts/run takes them from `rnav_clock --print-nodes`).
  std::vector<std::string> node_names() const { return {"target", "uav", "uav_tma", "uav_logger"}; }
};

}  // namespace rnav
