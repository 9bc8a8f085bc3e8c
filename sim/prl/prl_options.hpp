// Options of the landing radar (scenario sections "prl" and "prl_effects"), with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

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

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(PrlOptions& o, V& v) {
  v.num("period_s", o.period_s, 0.01, 60);
  v.num("phase_s", o.phase_s, 0, 60);
  v.num("max_range_m", o.max_range_m, 100, 500000);
  v.num("bias_range_m", o.bias_range_m, -1000, 1000);
  v.num("bias_course_deg", o.bias_course_deg, -10, 10);
  v.num("bias_glide_deg", o.bias_glide_deg, -10, 10);
  v.num("noise2s_range_m", o.noise2s_range_m, 0, 1000);
  v.num("noise2s_course_deg", o.noise2s_course_deg, 0, 10);
  v.num("noise2s_glide_deg", o.noise2s_glide_deg, 0, 10);
  v.num("drift_sigma_range_m", o.drift_sigma_range_m, 0, 1000);
  v.num("drift_sigma_course_deg", o.drift_sigma_course_deg, 0, 10);
  v.num("drift_sigma_glide_deg", o.drift_sigma_glide_deg, 0, 10);
  v.num("drift_tau_s", o.drift_tau_s, 1, kInf);
}

template <class V> void visit(PrlEffectsOptions& o, V& v) {
  v.num("range_gain", o.range_gain, -0.1, 0.1);
  v.num("time_offset_s", o.time_offset_s, -10, 10);
  v.num("elevation_refraction_rad", o.elevation_refraction_rad, -0.01, 0.01);
  v.num("azimuth_elevation_coupling_rad", o.azimuth_elevation_coupling_rad, -1, 1);
  v.num("site_offset_east_m", o.site_offset_east_m, -1000, 1000);
  v.num("site_offset_north_m", o.site_offset_north_m, -1000, 1000);
  v.num("site_offset_up_m", o.site_offset_up_m, -1000, 1000);
  v.num("drift_range_mps", o.drift_range_mps, -10, 10);
  v.num("drift_course_radps", o.drift_course_radps, -0.01, 0.01);
  v.num("drift_glide_radps", o.drift_glide_radps, -0.01, 0.01);
  v.num("step_time_s", o.step_time_s, -1, 1e6);
  v.num("step_range_m", o.step_range_m, -1000, 1000);
  v.num("step_course_rad", o.step_course_rad, -0.1, 0.1);
  v.num("step_glide_rad", o.step_glide_rad, -0.1, 0.1);
  v.num("noise_scale", o.noise_scale, 1e-3, 100);
  v.num("outlier_prob", o.outlier_prob, 0, 0.5);
  v.num("outlier_scale", o.outlier_scale, 1, 1000);
  v.num("correlated_noise_tau_s", o.correlated_noise_tau_s, 0, 1e5);
  v.num("periodic_period_s", o.periodic_period_s, 0, 1e5);
  v.num("periodic_range_m", o.periodic_range_m, -1000, 1000);
  v.num("periodic_course_rad", o.periodic_course_rad, -0.1, 0.1);
  v.num("periodic_glide_rad", o.periodic_glide_rad, -0.1, 0.1);
}

}  // namespace options_io
}  // namespace rnav
