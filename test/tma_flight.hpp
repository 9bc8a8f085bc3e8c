// Test fixture shared by the azimuth-only estimator tests (test_tma_batch_ml, test_tma_particle):
// a constant-velocity object and an observer on a circle or a straight pass, bearings with white
// sensor and nav noise generated from the project's models, the NEES and the chi-square band of a
// mean NEES, and the flight's PCRB at its end.
#pragma once

#include "common/physics/frames.hpp"
#include "common/physics/random.hpp"
#include "estimators/uav_tma/tma_batch_ml.hpp"
#include "estimators/uav_tma/tma_estimators.hpp"
#include "estimators/uav_tma/tma_models.hpp"
#include "estimators/uav_tma/tma_pcrb.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace rnav::tma::test_flight {

/// A flight of the observer past or around an object moving at constant velocity.
struct Flight {
  std::string path = "circle";  ///< "circle" about the object's first position, or "straight"
  double radius_m = 300;        ///< [m] circle radius; straight: distance of closest approach
  double speed_mps = 20;        ///< [m/s] observer ground speed
  double duration_s = 2 * M_PI * 300 / 20;  ///< [s] one orbit
  double period_s = 0.2;        ///< [s] bearing period
  double start_angle_rad = M_PI;  ///< circle: direction from the centre to the observer's start
  Vec4 x0{0, 0, 1 / std::sqrt(2.0), 1 / std::sqrt(2.0)};  ///< object at t = 0 [m, m/s]
  double sigma_b_rad = 0.5 * kDegToRad;  ///< bearing noise
  double sigma_nav_m = 0.3;              ///< observer nav noise per axis, white
};

inline Eigen::Vector2d observer_at(const Flight& f, double t) {
  if (f.path == "circle") {
    const double a = f.start_angle_rad + f.speed_mps / f.radius_m * t;
    return f.x0.head<2>() + f.radius_m * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
  // Straight pass heading east, closest approach (radius_m south of the object's first position)
  // half-way through.
  return f.x0.head<2>() + Eigen::Vector2d(-f.radius_m, f.speed_mps * (t - 0.5 * f.duration_s));
}

/// The bearings of one run: true bearing from the true observer plus sensor noise; the observer
/// position given is its nav solution (true + nav noise).
inline std::vector<BearingMeas> simulate(const Flight& f, Rng& rng) {
  std::vector<BearingMeas> v;
  const long n = std::lround(f.duration_s / f.period_s);
  for (long k = 0; k <= n; ++k) {
    BearingMeas z;
    z.t_s = k * f.period_s;
    const Vec4 x = cv_transition(z.t_s) * f.x0;
    const Eigen::Vector2d o = observer_at(f, z.t_s);
    z.bearing_rad = wrap_pi(bearing(x, o) + f.sigma_b_rad * rng.normal());
    z.sigma_rad = f.sigma_b_rad;
    z.p_obs_F = o + f.sigma_nav_m * Eigen::Vector2d(rng.normal(), rng.normal());
    z.sigma_nav_m = f.sigma_nav_m;
    v.push_back(z);
  }
  return v;
}

inline double nees(const Gaussian& g, const Vec4& truth) {
  const Vec4 e = g.x - truth;
  return e.dot(g.P.ldlt().solve(e));
}

/// Two-sided band of the mean of n independent chi-square(dof) variables: n * mean ~ chi2(n dof),
/// quantiles by Wilson-Hilferty (relative error far below 1e-3 at n dof in the hundreds).
inline std::pair<double, double> chi2_mean_band(long n, int dof, double z) {
  const double nu = static_cast<double>(n) * dof, a = 2.0 / (9.0 * nu);
  auto q = [&](double zz) { return nu * std::pow(1 - a + zz * std::sqrt(a), 3) / static_cast<double>(n); };
  return {q(-z), q(z)};
}

/// The PCRB of the flight's position at its last bearing: the prior information (built as the
/// filters build it, on the true first bearing) plus sum H^T H / R at the truth over the later
/// bearings, in theta = x(t0), transported to the end without process noise.
inline double pcrb_pos_end(const Flight& f, const TmaOptions& o) {
  const long n = std::lround(f.duration_s / f.period_s);
  const double sn2 = f.sigma_nav_m * f.sigma_nav_m;
  const double R0 = bearing_variance(f.sigma_b_rad, f.sigma_nav_m, o.range_prior_m);
  Mat4 J = prior_information(bearing(f.x0, observer_at(f, 0)), o.range_prior_m, o.range_sigma_m, R0, o.vel_sigma_mps);
  for (long k = 1; k <= n; ++k) {
    const double t = k * f.period_s;
    const Eigen::Vector2d ob = observer_at(f, t);
    const double D = range(cv_transition(t) * f.x0, ob);
    const Row4 H = batch_bearing_jacobian(f.x0, t, ob);
    J += H.transpose() * H / (f.sigma_b_rad * f.sigma_b_rad + sn2 / (D * D));
  }
  const Mat4 F = cv_transition(n * f.period_s);
  const Mat4 B = F * J.inverse() * F.transpose();
  return std::sqrt(B(kN, kN) + B(kE, kE));
}


}  // namespace rnav::tma::test_flight
