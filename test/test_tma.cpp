// Azimuth-only models, Kalman core, estimators and PCRB (estimators/uav_tma).
#include <catch2/catch.hpp>

#include "common/physics/frames.hpp"
#include "estimators/uav_tma/kalman_core.hpp"
#include "estimators/uav_tma/tma_estimators.hpp"
#include "estimators/uav_tma/tma_models.hpp"
#include "estimators/uav_tma/tma_pcrb.hpp"

#include <cmath>

using namespace rnav;
using namespace rnav::tma;

TEST_CASE("bearing Jacobian matches central finite differences, also across +-180 deg", "[tma]") {
  const Eigen::Vector2d obs(100.0, -50.0);
  // Target north-east, west (bearing near +-180 deg), south, and close by.
  for (const Vec4& x : {Vec4(800, 400, 1, 1), Vec4(-400, -50.1, 0, 0), Vec4(-400, -49.9, 0, 0),
                       Vec4(-300, 200, -1, 2), Vec4(103, -46, 0, 0)}) {
    const Row4 H = bearing_jacobian(x, obs);
    for (int i = 0; i < 4; ++i) {
      const double h = 1e-4;
      Vec4 xp = x, xm = x;
      xp[i] += h;
      xm[i] -= h;
      // The difference is wrapped: near +-pi the bearing jumps by 2 pi.
      const double fd = wrap_pi(bearing(xp, obs) - bearing(xm, obs)) / (2 * h);
      INFO("state " << x.transpose() << " component " << i);
      CHECK(H(i) == Approx(fd).margin(1e-9).epsilon(1e-6));
    }
  }
}

TEST_CASE("an update across the +-180 deg bearing uses the small wrapped innovation", "[tma]") {
  // Object due south-west-ish so that its bearing is near +-180 deg from the observer.
  TmaOptions o;
  CartesianEkf ekf(o, 500, 100);
  BearingMeas z;
  z.sigma_rad = 0.5 * kDegToRad;
  z.p_obs_F = Eigen::Vector2d(0, 0);
  z.bearing_rad = 179.9 * kDegToRad;  // initialise just left of 180
  ekf.process(z);
  const Gaussian before = ekf.estimate();
  z.t_s = 0.2;
  z.bearing_rad = -179.9 * kDegToRad;  // 0.2 deg further, across the wrap
  const double nis = ekf.process(z);
  const Gaussian after = ekf.estimate();
  // Unwrapped, the innovation would be -359.8 deg: NIS ~ 1e6 and a jump of kilometres.
  CHECK(nis < 1.0);
  CHECK((after.x.head<2>() - before.x.head<2>()).norm() < 5.0);
  CHECK(std::abs(wrap_pi(bearing(after.x, z.p_obs_F) - z.bearing_rad)) < 0.2 * kDegToRad);
}

TEST_CASE("Joseph update: symmetric positive definite, equal to the standard form", "[tma]") {
  Gaussian g;
  g.x << 300, 400, 1, -1;
  g.P = Mat4::Identity();
  g.P.topLeftCorner<2, 2>() << 400, 120, 120, 900;
  g.P(2, 2) = g.P(3, 3) = 4;
  g.P(0, 2) = g.P(2, 0) = 10;
  const Eigen::Vector2d obs(0, 0);
  const Row4 H = bearing_jacobian(g.x, obs);
  const double R = std::pow(0.5 * kDegToRad, 2);
  const Mat4 P0 = g.P;
  const double S = (H * P0 * H.transpose())(0, 0) + R;
  const Vec4 K = P0 * H.transpose() / S;
  const Mat4 standard = P0 - K * S * K.transpose();
  const ScalarUpdate u = update(g, 0.01, H, R);
  CHECK(u.S == Approx(S).epsilon(1e-12));
  CHECK((g.P - g.P.transpose()).norm() == 0.0);
  CHECK((g.P - standard).norm() < 1e-9 * P0.norm());
  Eigen::SelfAdjointEigenSolver<Mat4> es(g.P);
  CHECK(es.eigenvalues().minCoeff() > 0);
  CHECK(u.nis == Approx(0.01 * 0.01 / S).epsilon(1e-12));
}

TEST_CASE("CV process noise composes exactly over split intervals", "[tma]") {
  // Q(a + b) = F(b) Q(a) F(b)^T + Q(b) for white-acceleration noise.
  const double q = 0.3, a = 0.7, b = 1.9;
  const Mat4 lhs = cv_process_noise(q, a + b);
  const Mat4 rhs = cv_transition(b) * cv_process_noise(q, a) * cv_transition(b).transpose() +
                   cv_process_noise(q, b);
  CHECK((lhs - rhs).norm() < 1e-12);
  CHECK((cv_transition(a) * cv_transition(b) - cv_transition(a + b)).norm() < 1e-12);
}

TEST_CASE("PCRB equals the closed form for a static object seen from a circle", "[tma][pcrb]") {
  // N bearings at one instant from observers equally spaced on a circle of radius R around a
  // static object, noise sigma, a negligible prior eps: the position information is
  // sum_i u_i u_i^T / (R^2 sigma^2) with u_i the unit vector across the line of sight;
  // for N >= 3 equally spaced directions sum u_i u_i^T = N/2 I, so the bound per axis is
  //   var = 1 / (N / (2 R^2 sigma^2) + eps),   pos RMSE bound = sqrt(2 var).
  const double R = 300, sigma = 0.5 * kDegToRad, eps = 1e-9;
  for (const int N : {3, 8, 100}) {
    TmaPcrb b(eps * Mat4::Identity());
    const Vec4 x(0, 0, 0, 0);
    for (int i = 0; i < N; ++i) {
      const double th = 2 * M_PI * i / N + 0.3;
      const Eigen::Vector2d obs(R * std::cos(th), R * std::sin(th));
      b.predict(0.0, 0.0);
      b.update(bearing_jacobian(x, obs), sigma * sigma);
    }
    const double var = 1.0 / (N / (2 * R * R * sigma * sigma) + eps);
    INFO("N = " << N);
    CHECK(b.bound()(kN, kN) == Approx(var).epsilon(1e-6));
    CHECK(b.bound()(kE, kE) == Approx(var).epsilon(1e-6));
    CHECK(std::abs(b.bound()(kN, kE)) < 1e-6 * var);
    CHECK(b.pos_rmse_m() == Approx(std::sqrt(2 * var)).epsilon(1e-6));
  }
}

TEST_CASE("PCRB time update: exact information transport without process noise, "
          "and the general form reduces to it as q -> 0", "[tma][pcrb]") {
  Mat4 J = Mat4::Identity();
  J(0, 2) = J(2, 0) = 0.3;
  J(1, 1) = 2;
  TmaPcrb a(J), b(J);
  a.predict(3.0, 0.0);
  b.predict(3.0, 1e-12);
  const Mat4 Fi = cv_transition(-3.0);
  CHECK((a.information() - Fi.transpose() * J * Fi).norm() < 1e-12);
  CHECK((a.information() - b.information()).norm() < 1e-6);
  // Process noise only ever loses information.
  TmaPcrb c(J);
  c.predict(3.0, 0.1);
  CHECK(c.bound().trace() > a.bound().trace());
}

TEST_CASE("the PCRB prior is the EKF's initial covariance", "[tma][pcrb]") {
  TmaOptions o;
  CartesianEkf ekf(o, 600, 400);
  BearingMeas z;
  z.bearing_rad = 0.7;
  z.sigma_rad = 0.5 * kDegToRad;
  z.sigma_nav_m = 0.3;
  z.p_obs_F = Eigen::Vector2d(10, 20);
  ekf.process(z);
  const double Rb = bearing_variance(z.sigma_rad, z.sigma_nav_m, 600);
  const Mat4 J0 = prior_information(0.7, 600, 400, Rb, o.vel_sigma_mps);
  CHECK((J0 * ekf.estimate().P - Mat4::Identity()).norm() < 1e-9);
  // Its mean lies on the first bearing at the prior range.
  CHECK(range(ekf.estimate().x, z.p_obs_F) == Approx(600).epsilon(1e-12));
  CHECK(bearing(ekf.estimate().x, z.p_obs_F) == Approx(0.7).epsilon(1e-12));
}

TEST_CASE("RP-EKF: weights form a distribution and favour the true range", "[tma]") {
  TmaOptions o;
  RangeParameterisedEkf bank(o);
  REQUIRE(bank.weights().size() == static_cast<std::size_t>(o.bank_size));
  // A static object at 1000 m north; the observer flies east at 20 m/s: bearings without noise.
  const Vec4 truth(1000, 0, 0, 0);
  for (int k = 0; k <= 150; ++k) {
    BearingMeas z;
    z.t_s = 0.2 * k;
    z.p_obs_F = Eigen::Vector2d(0, -300 + 20 * z.t_s);
    z.sigma_rad = 0.5 * kDegToRad;
    z.bearing_rad = bearing(truth, z.p_obs_F);
    bank.process(z);
    double s = 0;
    for (double w : bank.weights()) {
      CHECK(w >= 0);
      s += w;
    }
    CHECK(s == Approx(1.0).epsilon(1e-12));
  }
  const Gaussian g = bank.estimate();
  // After a 600 m baseline the mixture is close to the truth and its covariance covers the error.
  const Vec4 e = g.x - truth;
  CHECK(e.head<2>().norm() < 50);
  CHECK(e.dot(g.P.ldlt().solve(e)) < 18.5);  // chi2(4) 99.9 % quantile
}
