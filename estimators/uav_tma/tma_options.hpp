// Options of the azimuth-only estimators (UAV scenario section "tma"), with their keys and checks.
#pragma once

#include "common/io/options_io.hpp"
#include "common/io/tma_estimator_names.hpp"

namespace rnav {

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
/// Throws ConfigError (naming tma.bank_min_m) unless bank_min_m < bank_max_m.
void check_tma(const TmaOptions& o);

namespace options_io {  // the visit() overloads must be found by read_section's ADL

template <class V> void visit(TmaOptions& o, V& v) {
  v.num("q_m2ps3", o.q_m2ps3, 0, 100);
  v.num("range_prior_m", o.range_prior_m, 1, 1e6);
  v.num("range_sigma_m", o.range_sigma_m, 1, 1e6);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 1e-3, 100);
  v.integer("bank_size", o.bank_size, 2, 64);
  v.num("bank_min_m", o.bank_min_m, 1, 1e6);
  v.num("bank_max_m", o.bank_max_m, 1, 1e6);
  v.flag("add_nav_noise", o.add_nav_noise);
  v.integer("pf_particles", o.pf_particles, 100, 1000000);
  v.choices("estimators", o.estimators, TmaOptions::known_estimators());
}

}  // namespace options_io
}  // namespace rnav
