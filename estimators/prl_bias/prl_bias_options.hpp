// Options of the radar systematic-error estimator (scenario section "prl_bias"), with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

/// Estimator of the radar's systematic error (docs/method.md section 1).
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

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(PrlBiasOptions& o, V& v) {
  v.num("switch_time_s", o.switch_time_s, 0, 1e6);
  v.num("delta_range_m", o.delta_range_m, 1e-6, 1e4);
  v.num("delta_course_deg", o.delta_course_deg, 1e-9, 10);
  v.num("delta_glide_deg", o.delta_glide_deg, 1e-9, 10);
  v.num("tau_s", o.tau_s, 1, kInf);
  v.num("noise2s_range_m", o.noise2s_range_m, 1e-6, 1000);
  v.num("noise2s_course_deg", o.noise2s_course_deg, 1e-9, 10);
  v.num("noise2s_glide_deg", o.noise2s_glide_deg, 1e-9, 10);
  v.flag("add_nav_variance", o.add_nav_variance);
  v.num("nav_wait_s", o.nav_wait_s, 0, 60);
  v.num("max_nav_gap_s", o.max_nav_gap_s, 0.01, 60);
  v.flag("compensate_during_estimation", o.compensate_during_estimation);
}

}  // namespace options_io
}  // namespace rnav
