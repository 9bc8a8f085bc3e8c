// Options of the SNS/INS navigation solution (scenario section "snsins"), with their keys.
#pragma once

#include "common/io/options_io.hpp"

namespace rnav {

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

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(SnsinsOptions& o, V& v) {
  v.num("link_period_s", o.link_period_s, 0.01, 60);
  v.num("link_phase_s", o.link_phase_s, 0, 60);
  v.num("latency_s", o.latency_s, 0, 10);
  v.num("corr_sigma_m", o.corr_sigma_m, 0, 1000);
  v.num("corr_tau_s", o.corr_tau_s, 0.01, kInf);
  v.num("white_sigma_m", o.white_sigma_m, 0, 1000);
  v.num("sns_period_s", o.sns_period_s, 0.001, 10);
  v.num("ins_tau_s", o.ins_tau_s, 0, 10000);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 0, 100);
  v.intervals("dropouts", o.dropouts, 0, 1e6);
}

}  // namespace options_io
}  // namespace rnav
