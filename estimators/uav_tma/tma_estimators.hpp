// Azimuth-only estimators of the object's position and velocity.
//  - CartesianEkf ("ekf"): the paper's linearised Kalman filter in its block structure:
//      a priori state X_bar = Phi X_hat; conversion A_bar = atan2(e - e_uav, n - n_uav),
//      D_bar = range; update with the wrapped bearing innovation (Joseph form).
//    Initialisation without truth: the first bearing plus a range prior (range_prior_m +-
//    range_sigma_m), zero velocity +- vel_sigma_mps.
//  - RangeParameterisedEkf ("rpekf"): a bank of CartesianEkf started at ranges spaced
//    geometrically over [bank_min_m, bank_max_m] (each with sigma_r proportional to its range),
//    weighted by their innovation likelihoods; the output is the mixture's mean and covariance.
//    It removes the single EKF's dependence on one range guess, the cause of its early
//    over-confidence (Peach 1995; Arulampalam & Ristic 2000).
//  - BatchMl ("ml", tma_batch_ml.hpp): the batch MAP estimate over all bearings so far.
//  - ParticleFilter ("pf", tma_particle.hpp): a regularised particle filter (the whole posterior
//    as weighted samples; random, from the realization's own stream).
#pragma once

#include "estimators/uav_tma/kalman_core.hpp"
#include "estimators/uav_tma/tma_options.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rnav::tma {

/// One bearing with everything the update needs.
struct BearingMeas {
  double t_s = 0;              ///< [s] time of validity
  double bearing_rad = 0;      ///< [rad] measured bearing, clockwise from north
  double sigma_rad = 0;        ///< [rad] sensor 1 sigma
  Eigen::Vector2d p_obs_F;     ///< [m] observer position from its nav solution (north, east)
  double sigma_nav_m = 0;      ///< [m] the nav solution's 1 sigma per axis
};

class TmaEstimator {
 public:
  virtual ~TmaEstimator() = default;
  virtual std::string name() const = 0;
  virtual bool initialized() const = 0;
  /// Predict to z.t_s and update with z (the first bearing initialises). Returns the NIS.
  virtual double process(const BearingMeas& z) = 0;
  /// Predict to t_s >= the last time (no measurement).
  virtual void predict_to(double t_s) = 0;
  virtual Gaussian estimate() const = 0;
};

class CartesianEkf : public TmaEstimator {
 public:
  /// @param range_m, range_sigma_m  the range prior used at initialisation
  CartesianEkf(const TmaOptions& o, double range_m, double range_sigma_m);
  std::string name() const override { return "ekf"; }
  bool initialized() const override { return init_; }
  double process(const BearingMeas& z) override;
  void predict_to(double t_s) override;
  Gaussian estimate() const override { return g_; }
  /// Log-likelihood of the last update's innovation.
  double last_log_lik() const { return last_log_lik_; }

 private:
  TmaOptions o_;
  double r0_, sr_;
  bool init_ = false;
  double t_s_ = 0, last_log_lik_ = 0;
  Gaussian g_;
};

class RangeParameterisedEkf : public TmaEstimator {
 public:
  explicit RangeParameterisedEkf(const TmaOptions& o);
  std::string name() const override { return "rpekf"; }
  bool initialized() const override { return init_; }
  double process(const BearingMeas& z) override;
  void predict_to(double t_s) override;
  Gaussian estimate() const override;
  const std::vector<double>& weights() const { return w_; }

 private:
  TmaOptions o_;
  bool init_ = false;
  std::vector<CartesianEkf> bank_;
  std::vector<double> w_;
};

/// NIS of a bearing against a Gaussian prediction (wrapped innovation).
double bearing_nis(const Gaussian& predicted, const BearingMeas& z, bool add_nav_noise);

/// The estimators named in o.estimators, in that order: "ekf" (CartesianEkf), "rpekf"
/// (RangeParameterisedEkf), "ml" (BatchMl, tma_batch_ml.hpp), "pf" (ParticleFilter,
/// tma_particle.hpp, whose random stream is that of (seed, realization)); by default the paper's
/// EKF and the RP-EKF bank. An unknown name throws std::invalid_argument (the scenario reader
/// rejects it first).
std::vector<std::unique_ptr<TmaEstimator>> make_estimators(const TmaOptions& o, std::uint64_t seed,
                                                           std::uint64_t realization);

}  // namespace rnav::tma
