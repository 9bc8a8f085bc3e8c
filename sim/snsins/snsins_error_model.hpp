// Error of the SNS/INS navigation solution, per axis of L (independent axes):
//   e = e_corr + e_smooth
//   e_corr:   Gauss-Markov, sigma = corr_sigma_m, T = corr_tau_s (SNS time-correlated error)
//   e_smooth: the SNS white error (white_sigma_m at sns_period_s) after the INS smoothing, a
//             first-order filter with time constant ins_tau_s: y(k+1) = (1-a) y(k) + a x(k),
//             a = sns_period_s / ins_tau_s, i.e. Gauss-Markov with phi = 1 - a per fix and
//             sigma_s = white_sigma_m sqrt(a / (2 - a)). ins_tau_s = 0: no smoothing (white).
// Velocity error: white, vel_sigma_mps per axis.
#pragma once

#include "common/physics/random.hpp"
#include "sim/snsins/snsins_options.hpp"

#include <Eigen/Dense>

#include <array>

namespace rnav {

class SnsinsErrorModel {
 public:
  explicit SnsinsErrorModel(const SnsinsOptions& o);
  /// Start a realization: draw the initial correlated states from their stationary law.
  void start(Rng& rng);
  /// Advance to t_s (non-decreasing) and draw the errors there.
  void step(double t_s, Rng& rng);
  const Eigen::Vector3d& dp_L() const { return dp_; }  ///< [m] position error, frame L
  const Eigen::Vector3d& dv_L() const { return dv_; }  ///< [m/s] velocity error, frame L
  /// [m] stationary RMS position error per axis: sqrt(sigma_corr^2 + sigma_smooth^2).
  double sigma_pos_m() const;
  /// [m] stationary sigma of the smoothed white part.
  double sigma_smooth_m() const { return sigma_smooth_; }

 private:
  SnsinsOptions o_;
  double sigma_smooth_ = 0, tau_smooth_ = 0;
  std::array<GaussMarkov, 3> corr_, smooth_;
  double t_s_ = 0;
  Eigen::Vector3d dp_ = Eigen::Vector3d::Zero(), dv_ = Eigen::Vector3d::Zero();
};

}  // namespace rnav
