// The landing-approach scenario: every option of every process, with unit, default and range.
//
// One JSON file configures all processes; each process loads the whole file (so a misspelt
// key anywhere is an error in every process, naming it) and uses its own sections.
// Defaults reproduce the paper's conditions (../shared/docs/method.md) plus the documented
// choices for what the paper leaves open (speed, lateral path, radar site, airfield).
#pragma once

#include "config.hpp"
#include "frames.hpp"

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace rnav {

/// Runway: origin and orientation of the landing frame L.
struct RunwayOptions {
  /// Threshold on WGS84. Default: Vienna (LOWW) runway 29 threshold, approximate public
  /// coordinates (not from the AIP); the airfield of our real ADS-B approaches.
  Geodetic threshold{48.10153, 16.58495, 228.0};
  double heading_deg = 295.9;  ///< landing true heading [deg], [0, 360)
};

/// Radar (PRL) site and azimuth reference. Site given in L, surveyed (known to the estimator).
struct RadarSiteOptions {
  double x_m = -900.0;  ///< [m] along the runway axis from the threshold (negative: beside the runway), [-5000, 5000]
  double z_m = 180.0;   ///< [m] lateral offset from the centreline in L, [-3000, 3000]
  double antenna_height_m = 4.0;  ///< [m] antenna above the threshold's ellipsoidal height, [0, 100]
  /// [deg] true bearing of the radar's x-axis (course angle 0); default: the runway axis
  /// pointing away from the runway (landing heading + 180). [0, 360)
  double azimuth_reference_deg = -1;  // -1 = default, resolved in Scenario::load
};

/// Aircraft path in L (paper: start x = 30860 m, z = 9860 m, y = 400 m; level, then 2 deg 40').
/// Lateral path: a straight leg from the start towards the centreline point (intercept_x_m, 0),
/// a coordinated turn at bank_deg onto the centreline, then straight in. Constant ground speed.
struct TrajectoryOptions {
  double start_x_m = 30860;   ///< [m] paper
  double start_y_m = 400;     ///< [m] paper; also the level-leg height in L
  double start_z_m = 9860;    ///< [m] paper
  double speed_mps = 75;      ///< [m/s] horizontal ground speed (our choice: a military approach speed), [10, 300]
  double intercept_x_m = 27000;  ///< [m] where the first leg would cross the centreline (our choice)
  double bank_deg = 25;       ///< [deg] bank angle of the turn onto final (our choice), [1, 60]
  double glide_deg = 2.0 + 40.0 / 60.0;  ///< [deg] descent angle 2 deg 40' (paper), (0, 10]
  double aim_x_m = -300;      ///< [m] where the glide path meets y = 0 (our choice: touchdown zone)
  double end_x_m = 0;         ///< [m] the run ends when the aircraft reaches this x on final
  double step_s = 0.25;       ///< [s] truth sample step; radar and nav sample times lie on this grid
  /// Replay a recorded approach instead of the analytic path above: a CSV file with columns
  /// t_s,lat_deg,lon_deg,h_m (time [s], strictly increasing; WGS84 latitude and longitude
  /// [deg]; height above the WGS84 ellipsoid [m]), e.g. written by rnav_import_adsb. Its first
  /// row is sim time 0 and its last row ends the run. "" (default) = the analytic path, and the
  /// keys above except step_s are then the only geometry. A relative path is relative to the
  /// scenario file's directory (relative to the working directory when it comes from --set).
  std::string replay_csv;
  /// [s] half-width W of the replay's smoothing window: position and velocity at t are those
  /// of a least-squares quadratic in time fitted to the samples within |t_i - t| < W, weighted
  /// (1 - |t_i - t|^3 / W^3)^3. Larger W: less ADS-B noise, more rounded turns. [1, 300];
  /// must exceed 2 * the largest time step of the file (at least 3 samples in every window).
  double replay_smoothing_s = 30;
  /// [s] largest time step allowed between consecutive rows of replay_csv (a longer gap is an
  /// error naming the line: the replay would invent the path across it), (0, 120]
  double replay_max_gap_s = 15;
};

/// Landing radar error model (Table 1) and schedule.
struct PrlOptions {
  double period_s = 1.0;       ///< [s] plot period (update rate), multiple of trajectory.step_s
  double phase_s = 0.0;        ///< [s] time of the first plot, multiple of trajectory.step_s
  double max_range_m = 40000;  ///< [m] no plots beyond this slant range
  double bias_range_m = 6;     ///< [m] constant systematic range error (Table 1)
  double bias_course_deg = 0.1;  ///< [deg] constant systematic course-angle error (Table 1)
  double bias_glide_deg = 0.15;  ///< [deg] constant systematic glide-angle error (Table 1)
  double noise2s_range_m = 24;   ///< [m] fluctuation error, 2 sigma (Table 1)
  double noise2s_course_deg = 0.5;  ///< [deg] fluctuation, 2 sigma (Table 1)
  double noise2s_glide_deg = 0.6;   ///< [deg] fluctuation, 2 sigma (Table 1)
  double drift_sigma_range_m = 0;   ///< [m] slowly varying (Gauss-Markov) part of the systematic error, 1 sigma
  double drift_sigma_course_deg = 0;  ///< [deg] idem, course
  double drift_sigma_glide_deg = 0;   ///< [deg] idem, glide
  double drift_tau_s = 600;         ///< [s] correlation time of the drift
};

/// Further radar error effects (the diagnosis catalogue), all off by default, so tests and users
/// can make data with a known hidden effect. Names match `scripts/diagnose`'s catalogue.
struct PrlEffectsOptions {
  double range_gain = 0;              ///< range_gain: dD = g D [1], |g| <= 0.1
  double time_offset_s = 0;           ///< time_offset: radar time stamp minus true time [s]: dzeta = -zeta_dot tau
  double elevation_refraction_rad = 0;  ///< elevation_refraction: dEg = k cot(Eg) [rad]
  double azimuth_elevation_coupling_rad = 0;  ///< azimuth_elevation_coupling: dEk = c tan(Eg) [rad]
  double site_offset_east_m = 0;      ///< site_offset: surveyed site minus true site, east [m]
  double site_offset_north_m = 0;     ///< idem, north [m]
  double site_offset_up_m = 0;        ///< idem, up [m]
  double drift_range_mps = 0;         ///< bias_drift: d(range bias)/dt [m/s]
  double drift_course_radps = 0;      ///< bias_drift: course [rad/s]
  double drift_glide_radps = 0;       ///< bias_drift: glide [rad/s]
  double step_time_s = -1;            ///< bias_step: time of the step [s] (-1: none)
  double step_range_m = 0;            ///< bias_step: range step [m]
  double step_course_rad = 0;         ///< bias_step: course step [rad]
  double step_glide_rad = 0;          ///< bias_step: glide step [rad]
  double noise_scale = 1;             ///< noise_scale: fluctuation sigma multiplier, (0, 100]
  double outlier_prob = 0;            ///< outliers: probability per plot, [0, 0.5]
  double outlier_scale = 10;          ///< outliers: their sigma in units of the fluctuation sigma
  double correlated_noise_tau_s = 0;  ///< correlated_noise: fluctuation as AR(1) with this correlation time [s] (0: white)
  double periodic_period_s = 0;       ///< periodic: period [s] (0: none)
  double periodic_range_m = 0;        ///< periodic: range amplitude [m]
  double periodic_course_rad = 0;     ///< periodic: course amplitude [rad]
  double periodic_glide_rad = 0;      ///< periodic: glide amplitude [rad]
};

/// SNS/INS navigation solution as received on the ground.
struct SnsinsOptions {
  double link_period_s = 0.5;  ///< [s] data-link period, multiple of trajectory.step_s
  double link_phase_s = 0.25;  ///< [s] validity time of the first solution, multiple of trajectory.step_s
  double latency_s = 0.3;      ///< [s] data-link latency (arrival minus validity), [0, 10]
  double corr_sigma_m = 1.9;   ///< [m] time-correlated SNS error per axis, 1 sigma
  double corr_tau_s = 120;     ///< [s] its correlation time
  double white_sigma_m = 0.62; ///< [m] white SNS error per axis, 1 sigma (total RMS sqrt(1.9^2+0.62^2) = 2.0 m)
  double sns_period_s = 0.1;   ///< [s] SNS fix period (for the INS smoothing of the white part)
  double ins_tau_s = 10;       ///< [s] INS smoothing time constant of the white part; 0 = no smoothing
  double vel_sigma_mps = 0.05; ///< [m/s] velocity error per axis, 1 sigma, white
  std::vector<std::pair<double, double>> dropouts;  ///< [s] intervals with no solutions sent
};

/// The navigation data link from the aircraft to the ground receiver at the radar
/// (sim/datalink/link_budget.hpp has the equations). Off by default: snsins then publishes
/// NAV_SOLUTION itself, as before. On: snsins publishes what the aircraft sends on
/// NAV_SOLUTION_TX and the node "datalink" republishes on NAV_SOLUTION the messages that survive,
/// each lost with probability p_loss(d) at the slant range d from the nav solution's position to
/// the radar antenna. The transmitter is peak-power limited: P_mean = peak_power_w / PF^2, PF the
/// family's peak factor for this code length and filter, computed at start-up.
struct DatalinkOptions {
  bool enabled = false;           ///< model the link (adds the node "datalink")
  double peak_power_w = 1.0;      ///< [W] transmitter peak envelope power, [1e-15, 1e9]
  /// Spreading-code family: "gold", "gold-qpsk" (Gold codes on I and Q), "ab2", "ab3", "tent"
  /// (binary Bernoulli-map AB codes), "ab2-phase", "ab3-phase", "tent-phase" (polyphase AB codes);
  /// see sim/datalink/ab_codes.hpp and the README's code study.
  std::string family = "gold";
  long code_length = 127;         ///< [chips] per data bit: 127, 511 or 1023
  std::string filter = "rc";      ///< band-limiting filter: "rc" (raised cosine) or "brick" (ideal low-pass)
  double bandwidth_chips = 0.5;   ///< [chip rates] B: the filter's -6 dB (rc) or cut-off (brick) frequency, [1e-3, 100]
  double rolloff = 0.25;          ///< [1] raised-cosine roll-off beta, [1e-3, 1] (unused by "brick")
  /// [1] which peak factor of the family the transmitter must allow for: this quantile of PF over
  /// pf_codes codes (0.5: the median code, the code study's figure; 1: the worst), [0, 1]
  double pf_quantile = 0.5;
  long pf_codes = 129;            ///< codes the PF quantile is taken over, [2, 4096] (Gold: at most N + 2)
  long samples_per_chip = 24;     ///< waveform samples per chip for the PF, [4, 256]; the band edge must lie below half of it
  double chip_rate_hz = 10.16e6;  ///< [chips/s] R_c, [1, 1e11]; bit rate R_c / code_length (80 kbit/s at 127)
  double frequency_hz = 1.0e9;    ///< [Hz] carrier, [1e6, 1e12]
  double tx_gain_dbi = 0;         ///< [dBi] aircraft antenna gain towards the ground, [-50, 60]
  double rx_gain_dbi = 3;         ///< [dBi] ground antenna gain, [-50, 60]
  double noise_figure_db = 5;     ///< [dB] ground receiver noise figure, [0, 40]
  double noise_temperature_k = 290;  ///< [K] reference noise temperature T0, [1e-3, 1e5]
  double system_loss_db = 10;     ///< [dB] cables, antenna pattern, implementation and a fading margin, [0, 200]
  /// [bits] per navigation message (no FEC: lost if any bit is wrong), [1, 1e7]; its air time
  /// message_bits code_length / chip_rate_hz must not exceed snsins.link_period_s
  long message_bits = 256;
};

/// Estimator of the radar's systematic error (method.md section 1).
struct PrlBiasOptions {
  double switch_time_s = 400;     ///< [s] estimation before, compensation after (paper)
  double delta_range_m = 10;      ///< [m] delta: prior 1 sigma of the bias (Gauss-Markov model)
  double delta_course_deg = 0.2;  ///< [deg] idem, course
  double delta_glide_deg = 0.3;   ///< [deg] idem, glide
  double tau_s = 3600;            ///< [s] T: correlation time of the bias model
  double noise2s_range_m = 24;    ///< [m] assumed radar fluctuation, 2 sigma (radar spec = Table 1)
  double noise2s_course_deg = 0.5;  ///< [deg] idem
  double noise2s_glide_deg = 0.6;   ///< [deg] idem
  bool add_nav_variance = true;   ///< r = r1 + p2 (nav variance projected to polar) instead of r1
  double nav_wait_s = 1.0;        ///< [s] a plot waits at most this long for the nav solution after it
  double max_nav_gap_s = 2.0;     ///< [s] largest gap between nav solutions to interpolate over
  bool compensate_during_estimation = false;  ///< also compensate before the switch time
};

/// Ensemble statistics.
struct LoggerOptions {
  std::vector<double> table_ranges_m{25000, 4000};  ///< [m] Table 2 ranges (see table_range_origin)
  /// What a Table 2 "range" is measured from: "radar" (true slant range from the radar antenna)
  /// or "threshold" (true distance from the runway threshold). The paper does not say; its
  /// APOI values fit "threshold" (see README, "The paper scenario and our choices").
  std::string table_range_origin = "radar";
  double table_halfwidth_m = 250;  ///< [m] plots within +- this of a table range form its bin
  double range_bin_m = 1000;       ///< [m] width of the range bins of stats_range.csv
};

/// Lock-step protocol.
struct RunnerOptions {
  /// [s] sim time per lock-step window (batch size): 0 takes each realization as one window (the
  /// landing scenario's default: its nodes feed nothing back, so no result depends on the window,
  /// and one round trip per realization is fastest); else a multiple of the truth step (the
  /// landing scenario) or of sensor.period_s (the UAV scenario, whose default is 20 s and which
  /// needs windows > 0), [0, 1e5]
  double window_s = 0;
  double flush_s = 5;           ///< [s] sim time after the aircraft's last state, > prl_bias.nav_wait_s
  /// [s wall] the longest the clock waits for a window's next ack before it sends RESEND; the
  /// wait adapts to the run's own pace (twice the median over the last 32 windows of each
  /// window's slowest ack gap that no resend interrupted, at least 1 ms) and doubles with each resend
  /// in a row that no overdue node answered, up to this.
  /// [0.05, 600]
  double stall_timeout_s = 1;
  /// [s wall] a window not complete this long after its START, despite resends, repeats the
  /// realization. [0.1, 600]
  double ack_timeout_s = 6;
  long max_attempts = 3;        ///< attempts per realization before the run fails, [1, 100]
  /// [s wall] a node or the clock silent this long fails the run naming it: the clock names a
  /// node that neither acks nor answers RESEND; a node that hears nothing from the clock (it
  /// sends a heartbeat every peer_timeout_s / 8) stops. Must exceed the longest time a node
  /// takes to process one window. [0.5, 3600]
  double peer_timeout_s = 10;
  std::int64_t epoch_utime = 1767225600000000LL;  ///< [us since Unix epoch] sim time 0 (2026-01-01T00:00Z)
  /// How the data channels travel: "batch" (one message per channel and window, the fast
  /// ensemble's form) or "sample" (one message per sample, of the sample type: a prl_plot_t per
  /// radar plot, a nav_solution_t per solution; nothing in a window without samples; what
  /// lcm-spy and outside consumers expect; scripts/run --realtime chooses it). Every process
  /// of a run must use the same; the statistics are byte-identical either way.
  std::string wire = "batch";
};

struct Scenario {
  std::string name = "paper";
  RunwayOptions runway;
  RadarSiteOptions radar;
  TrajectoryOptions trajectory;
  PrlOptions prl;
  PrlEffectsOptions prl_effects;
  SnsinsOptions snsins;
  DatalinkOptions datalink;
  PrlBiasOptions prl_bias;
  LoggerOptions logger;
  RunnerOptions runner;

  /// Load and validate a scenario file with "a.b=value" overrides applied first.
  /// Throws ConfigError naming the key for unknown keys, wrong types, NaN, out-of-range values
  /// and inconsistent combinations.
  static Scenario load(const std::string& file, const std::vector<std::string>& overrides = {});
  /// Parse from an already-loaded JSON document.
  static Scenario from_json(const nlohmann::json& doc);

  /// Landing frame L at the threshold.
  LocalLevelFrame landing_frame() const;
  /// The radar site on WGS84.
  Geodetic radar_site() const;
  /// Radar frame R at the site, x along radar.azimuth_reference_deg.
  LocalLevelFrame radar_frame() const;

  /// Sim time [us] -> utime [us since Unix epoch].
  std::int64_t utime(std::int64_t t_us) const { return runner.epoch_utime + t_us; }

  /// The lock-step nodes a multi-process run starts, in the chain's order, each the process
  /// rnav_<name>: trajectory, snsins, datalink (only when datalink.enabled), prl, prl_bias, logger.
  /// scripts/run takes them from `rnav_clock --print-nodes`.
  std::vector<std::string> node_names() const;

  /// Human-readable dump of every option (printed by every process at start-up).
  void print(std::ostream& os) const;
};

/// Seconds -> integer microseconds (rounded).
std::int64_t to_us(double t_s);

}  // namespace rnav
