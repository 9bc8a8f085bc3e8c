// ParticleFilter ("pf"): a regularised sampling-importance-resampling (SIR) particle filter for
// azimuth-only tracking. It carries the whole posterior as M weighted samples of the Cartesian
// state x = (north, east, v_north, v_east) [m, m, m/s, m/s], so it needs neither a range guess
// nor a linearisation: a banana-shaped posterior early in a run, a range that a straight pass
// leaves unobserved, or a prior far from the truth are represented as they are.
//
// Initialisation (first bearing b0 from observer o0, variance R0 = the bearing variance at the
// sampled range): per particle i,
//   r_i ~ log-uniform on [tma.bank_min_m, tma.bank_max_m]   (the RP-EKF bank's span: the same
//         prior knowledge of the range, no single guess),
//   b_i ~ N(b0, R0(r_i)),  p_i = o0 + r_i (cos b_i, sin b_i),  v_i ~ N(0, tma.vel_sigma_mps^2 I),
//   w_i = 1 / M.
// Prediction over dt (the filters' constant-velocity model; exact sampling of its process noise):
//   x_i <- F(dt) x_i + L_Q(dt) n_i,  n_i ~ N(0, I_4),  L_Q L_Q^T = Q(dt) = tma.q_m2ps3 * [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]
//   (no noise when q = 0).
// Update with bearing z from observer o (R_i = the bearing variance at particle i's range with
// tma.add_nav_noise, else sigma_b^2):
//   nu_i = wrap(z - atan2(e_i - o_e, n_i - o_n)),  log w_i <- log w_i - nu_i^2 / (2 R_i) - log(R_i) / 2,
//   then normalised in the log domain.
// Resampling when the effective sample size ESS = 1 / sum w_i^2 falls below
// resample_fraction * M: systematic resampling (one uniform draw), then regularisation with the
// Liu-West shrinkage kernel, which keeps the cloud's mean xbar and covariance S (of the weighted
// cloud before resampling) while giving duplicated particles distinct values:
//   x_i <- a x_i + (1 - a) xbar + h L_S n_i,   a = sqrt(1 - h^2),  L_S L_S^T = S,
//   h = kernel_scale * (4 / (M (d + 2)))^(1 / (d + 4)),  d = 4   (Silverman's optimal Gaussian
//   kernel bandwidth for M samples in d dimensions).
// Without it, with q = 0 the duplicates would never separate and the cloud would collapse to a
// few points.
//
// Output: the weighted mean and covariance of the cloud (the MMSE estimate and its covariance).
// NIS (returned by process): the bearing against that Gaussian before the update, as the RP-EKF
// reports its.
//
// Random numbers: one stream per (ensemble seed, realization) (Stream::kTmaParticle), drawn in a
// fixed order, so a realization's estimates are byte-identical across runs, transports and
// window sizes.
//
// Cost: O(M) per bearing (one atan2 and one log per particle); about M x 942 particle updates per
// default UAV run.
#pragma once

#include "common/physics/random.hpp"
#include "estimators/uav_tma/tma_estimators.hpp"

#include <cstdint>
#include <vector>

namespace rnav::tma {

/// Numerical settings of ParticleFilter besides tma.pf_particles (not scenario keys).
struct ParticleSettings {
  double resample_fraction = 0.5;  ///< resample when ESS < this * M, in (0, 1]
  /// Multiplies Silverman's bandwidth (the product h must stay below 1), > 0. 1.5 (h = 0.46 at
  /// M = 8000): with 1.0 the default UAV run's mean NEES was 4.51 over 200 runs (above the
  /// chi-square band [3.62, 4.40]: the cloud loses its tails between resamplings); with 2.0 a
  /// straight pass's banana-shaped posterior was blurred into a Gaussian (NEES 19).
  double kernel_scale = 1.5;
};

/// Silverman's optimal Gaussian kernel bandwidth for m samples in d dimensions:
/// (4 / (m (d + 2)))^(1 / (d + 4)).
double silverman_bandwidth(long m, int d);

/// Systematic resampling: m indices, index j taken floor(m w_j + offset) - floor(m w_{<j} + offset)
/// times, u in [0, 1) the one uniform draw. w must be normalised (sum 1, each >= 0).
std::vector<int> systematic_resample(const std::vector<double>& w, double u);

/// The Liu-West shrinkage kernel on an equally weighted (resampled) cloud x whose source had mean
/// xbar and covariance S: x_i <- a x_i + (1 - a) xbar + h L n_i, a = sqrt(1 - h^2), L L^T = S,
/// n_i ~ N(0, I) from rng. If x's mean and covariance are xbar and S, they stay so in expectation:
/// E = a xbar + (1 - a) xbar = xbar, Cov = a^2 S + h^2 S = S. h in (0, 1).
void liu_west_regularise(std::vector<Vec4>& x, const Vec4& xbar, const Mat4& S, double h, Rng& rng);

class ParticleFilter : public TmaEstimator {
 public:
  /// @param o          tma options: pf_particles (M), bank_min_m/bank_max_m (range prior span),
  ///                   vel_sigma_mps, q_m2ps3, add_nav_noise
  /// @param seed       ensemble seed
  /// @param realization  realization index (with seed, selects the random stream)
  ParticleFilter(const TmaOptions& o, std::uint64_t seed, std::uint64_t realization,
                 const ParticleSettings& s = {});
  std::string name() const override { return "pf"; }
  bool initialized() const override { return init_; }
  double process(const BearingMeas& z) override;
  void predict_to(double t_s) override;
  Gaussian estimate() const override { return est_; }

  long resamples() const { return resamples_; }      ///< resampling steps so far
  double effective_sample_size() const;              ///< 1 / sum w_i^2 now
  const std::vector<Vec4>& particles() const { return x_; }
  const std::vector<double>& weights() const { return w_; }

 private:
  void initialise(const BearingMeas& z);
  void update(const BearingMeas& z);
  void resample();
  void refresh_estimate();

  TmaOptions o_;
  ParticleSettings s_;
  Rng rng_;
  bool init_ = false;
  double t_s_ = 0;
  long resamples_ = 0;
  std::vector<Vec4> x_;
  std::vector<double> w_;
  Gaussian est_;
};

}  // namespace rnav::tma
