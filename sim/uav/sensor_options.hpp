// Options of the UAV's passive sensor (UAV scenario sections "sensor" and "sensor_effects"),
// with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

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

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(SensorOptions& o, V& v) {
  v.num("sigma_deg", o.sigma_deg, 1e-4, 10);
  v.num("period_s", o.period_s, 0.01, 10);
  v.num("fov_centre_deg", o.fov_centre_deg, -180, 180);
  v.num("fov_half_deg", o.fov_half_deg, 0, 180);
  v.num("max_range_m", o.max_range_m, 1, 1e6);
  v.num("min_range_m", o.min_range_m, 0, 1e6);
}

template <class V> void visit(SensorEffectsOptions& o, V& v) {
  v.num("bearing_bias_rad", o.bearing_bias_rad, -0.2, 0.2);
  v.num("time_offset_s", o.time_offset_s, -10, 10);
  v.num("bias_drift_radps", o.bias_drift_radps, -0.01, 0.01);
  v.num("noise_scale", o.noise_scale, 1e-3, 100);
  v.num("correlated_noise_tau_s", o.correlated_noise_tau_s, 0, 1e5);
  v.num("outlier_prob", o.outlier_prob, 0, 0.5);
  v.num("outlier_scale", o.outlier_scale, 1, 1000);
  v.num("periodic_period_s", o.periodic_period_s, 0, 1e5);
  v.num("periodic_amplitude_rad", o.periodic_amplitude_rad, -0.2, 0.2);
}

}  // namespace options_io
}  // namespace rnav
