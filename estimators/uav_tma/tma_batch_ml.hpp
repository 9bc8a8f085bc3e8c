// BatchMl ("ml"): the batch maximum a posteriori (MAP) azimuth-only estimator. At every bearing
// it re-solves the whole problem over ALL bearings received so far, instead of carrying a
// linearisation forward as the filters do.
//
// Unknown: theta = x(t0), the object's state (north, east, v_north, v_east) [m, m, m/s, m/s] at
// the time t0 of the FIRST bearing; the state at any time t is propagated with the
// constant-velocity model
//   x(t) = F(t - t0) theta,  F(dt) = [[I, dt I], [0, I]],   P(t) = F(t - t0) Sigma F(t - t0)^T.
//
// Prior (the filters' own initialisation, so the estimate exists from the first bearing on): the
// first bearing b0 from observer o0, range prior r0 = tma.range_prior_m +- s_r = tma.range_sigma_m
// along it, zero velocity +- tma.vel_sigma_mps:
//   m0 = (o0 + r0 u0, 0, 0),  P0 = blockdiag(s_r^2 u0 u0^T + r0^2 R0 c0 c0^T, s_v^2 I),
// u0 = (cos b0, sin b0), c0 = (-sin b0, cos b0), R0 = the bearing variance at r0. The first
// bearing is in the prior (its cross-range term) and is not used again.
//
// Cost (negative log posterior x 2, up to a constant): over the bearings k = 1..N after the first,
//   C(theta) = (theta - m0)^T P0^-1 (theta - m0) + sum_k r_k(theta)^2 / R_k,
//   r_k = wrap(z_k - h_k(theta)) = atan2(sin z_k dn - cos z_k de, cos z_k dn + sin z_k de),
//   (dn, de) = p(t_k) - o_k,  p(t_k) = theta_p + (t_k - t0) theta_v,  D_k = |(dn, de)|,
//   R_k = sigma_b^2 + sigma_nav^2 / D_k^2 with tma.add_nav_noise (the filters' bearing variance,
//         evaluated at the current iterate and held fixed within one step), else sigma_b^2.
// The residual is the wrapped angle between the measured and the predicted line of sight, so a
// bearing near +-180 deg costs what it should. Since the prior is the filters' data-dependent
// initialisation, this is a MAP estimate under that prior, not a pure maximum-likelihood one.
//
// Jacobian (analytic; batch_bearing_jacobian, tested against finite differences):
//   dh_k/dtheta = [hn, he, dt_k hn, dt_k he],  hn = -de / D_k^2,  he = dn / D_k^2.
// Normal equations (Gauss-Newton), A the Fisher information at theta:
//   A = P0^-1 + sum_k J_k^T J_k / R_k,   g = P0^-1 (m0 - theta) + sum_k J_k^T r_k / R_k,
// step control: Levenberg-Marquardt, (A + lambda diag A) delta = g, a trial accepted only if its
// cost (with the same R_k) is below the current one, it is finite and every range D_k stays
// above kMinRange_m (the model is singular at D = 0; a state behind the observer costs about
// pi^2 / R per bearing and is rejected by the cost). lambda follows Nielsen's rule.
// Covariance: Sigma = A^-1 at the solution (prior information + sum of H^T R^-1 H), the same
// information the PCRB sums at the truth.
//
// Work per bearing (warm start, limited iterations): the previous solution theta is kept with
// A, g and C summed at it, so adding bearing N updates them in O(1). If the Newton decrement
// g^T A^-1 g (the cost reduction a full step would give, in chi-square units: theta is within
// sqrt(decrement) standard deviations of the quadratic model's optimum) is below
// `decrement_tol`, theta stands (no pass over the data). Otherwise at most `max_trials` LM trials
// follow, each one pass over all N bearings that evaluates C, A and g at the trial point (so an
// accepted trial needs no further pass). A frame whose trials run out keeps the best accepted
// point and continues from it at the next bearing. Work: at most max_trials x N bearing
// evaluations per bearing (so O(N^2) per run at worst max_trials times), in practice about one
// pass per bearing while the estimate moves and none once it has settled (`passes()` and
// `evaluations()` count them). The default UAV run (942 bearings): about 0.41 million evaluations,
// about 10 ms per run on the 2-core development machine.
//
// NIS (returned by process): the new bearing against the previous solution propagated to its
// time, nu^2 / (H P H^T + R), as the filters report theirs.
//
// Process noise: the batch assumes exactly constant velocity over the whole span and IGNORES
// tma.q_m2ps3. With a manoeuvring object (q > 0 needed by the filters) its model is wrong: the
// fit averages the track, its covariance keeps shrinking as 1/N, and its NEES is expected to
// leave the band after a turn. It is meant for the constant-velocity case.
#pragma once

#include "estimators/uav_tma/tma_estimators.hpp"

#include <vector>

namespace rnav::tma {

/// Numerical settings of BatchMl (not scenario keys: the defaults serve every scenario).
struct BatchMlSettings {
  int max_trials = 8;            ///< LM trial points (data passes) per bearing, >= 1
  double decrement_tol = 1e-4;   ///< Newton decrement g^T A^-1 g [chi-square units] below which theta stands, > 0
};

/// d h / d theta of a bearing at time t0 + dt_s from observer p_obs_F, the state theta = x(t0):
/// [hn, he, dt hn, dt he] with (hn, he) = (-de, dn) / D^2.
Row4 batch_bearing_jacobian(const Vec4& theta, double dt_s, const Eigen::Vector2d& p_obs_F);

class BatchMl : public TmaEstimator {
 public:
  static constexpr double kMinRange_m = 1e-3;  ///< [m] a trial with any range below this is rejected

  explicit BatchMl(const TmaOptions& o, const BatchMlSettings& s = {});
  std::string name() const override { return "ml"; }
  bool initialized() const override { return init_; }
  /// The first bearing sets the prior; each later one is added and the MAP problem re-solved
  /// (warm-started). Returns the NIS of z against the previous solution propagated to z.t_s.
  double process(const BearingMeas& z) override;
  /// Move the output time to t_s (>= the last time); the solution itself does not change.
  void predict_to(double t_s) override;
  /// x(t) = F theta, P(t) = F A^-1 F^T at the current output time.
  Gaussian estimate() const override;

  /// Run further LM trials (up to max_trials, stopping below decrement_tol) on the bearings held.
  void refine(int max_trials, double decrement_tol);
  /// The cost C(theta) over the bearings held (R_k evaluated at theta); +inf if a range is
  /// below kMinRange_m.
  double cost(const Vec4& theta) const;
  /// theta = x(t0), the current solution at the first bearing's time, and t0 [s].
  const Vec4& reference_state() const { return theta_; }
  double reference_time_s() const { return t0_; }
  /// The Fisher information A at theta (its inverse is the covariance of theta).
  const Mat4& information() const { return A_; }
  /// g = P0^-1 (m0 - theta) + sum_k J_k^T r_k / R_k at theta (R_k at theta): -1/2 the
  /// gradient of C when R does not depend on theta (tma.add_nav_noise false).
  const Vec4& gradient() const { return g_; }
  /// g^T A^-1 g at theta: how far theta is from the optimum of its quadratic model.
  double newton_decrement() const;
  std::size_t bearings() const { return obs_.size(); }
  long passes() const { return passes_; }          ///< passes over the data so far
  long evaluations() const { return evaluations_; }  ///< bearing residual evaluations so far

 private:
  struct Obs {
    double dt_s;        // t_k - t0
    double on, oe;      // observer position [m]
    double sz, cz;      // sin, cos of the measured bearing
    double sb2, sn2;    // sensor variance [rad^2], nav variance per axis [m^2]
  };
  /// Sums over bearings at one point theta.
  struct Sums {
    double cost = 0;        // sum r^2 / R(theta)
    double cost_held = 0;   // sum r^2 / R(theta_held): the cost with the weights of the step's start
    double a[9] = {};       // sum w h h^T (nn, ne, ee) x (1, dt, dt^2)
    double b[4] = {};       // sum w r h (n, e) x (1, dt)
  };
  struct Eval {
    double cost = 0, cost_held = 0;
    Mat4 A = Mat4::Zero();
    Vec4 g = Vec4::Zero();
  };
  /// One bearing at theta added to s (weights R at theta; cost_held with R at *held if given);
  /// false if its range is below kMinRange_m.
  bool add(const Obs& k, const Vec4& theta, const Vec4* held, Sums& s) const;
  /// The prior added and the sums arranged into C, A, g.
  Eval finish(const Sums& s, const Vec4& theta) const;
  /// C, A, g at theta over all bearings held; false if a range is below kMinRange_m or the cost
  /// is not finite.
  bool evaluate(const Vec4& theta, const Vec4* held, Sums& s, Eval& e) const;
  void solve(int max_trials, double decrement_tol);

  TmaOptions o_;
  BatchMlSettings s_;
  bool init_ = false;
  double t0_ = 0, t_ = 0;
  Vec4 m0_ = Vec4::Zero();   // prior mean
  Mat4 L0_ = Mat4::Zero();   // prior information P0^-1
  std::vector<Obs> obs_;
  Vec4 theta_ = Vec4::Zero();
  Mat4 A_ = Mat4::Zero();
  Vec4 g_ = Vec4::Zero();
  Sums sums_;                // at theta_, so that a new bearing is added in O(1)
  double cost_ = 0;
  double lambda_ = 1e-3, nu_ = 2;  // LM damping and its growth factor (Nielsen)
  mutable long passes_ = 0, evaluations_ = 0;
};

}  // namespace rnav::tma
