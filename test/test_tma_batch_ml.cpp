// The batch MAP azimuth-only estimator (estimators/uav_tma/tma_batch_ml.hpp) and its selection
// by the scenario key tma.estimators. The data are generated here from the project's models
// (constant-velocity truth, tma::bearing, white sensor and nav noise: test/tma_flight.hpp), not
// from scenario files.
#include <catch2/catch.hpp>

#include "common/physics/frames.hpp"
#include "common/physics/random.hpp"
#include "estimators/uav_tma/tma_batch_ml.hpp"
#include "estimators/uav_tma/tma_estimators.hpp"
#include "test/tma_flight.hpp"
#include "estimators/uav_tma/tma_models.hpp"
#include "estimators/uav_tma/tma_pcrb.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

using namespace rnav;
using namespace rnav::tma;
using namespace rnav::tma::test_flight;

TEST_CASE("ml: the batch bearing Jacobian matches central finite differences, also across +-180 deg",
          "[tma][ml]") {
  const Eigen::Vector2d obs(100.0, -50.0);
  // theta = x(t0); the bearing is taken dt later: object north-east, due west of the observer at
  // t0 + dt (bearing near +-180 deg, on either side), south, and close by.
  struct Case {
    Vec4 theta;
    double dt;
  };
  for (const Case& c : {Case{Vec4(800, 400, 1, 1), 30}, Case{Vec4(-430, -80.1, 1, 1), 30},
                        Case{Vec4(-430, -79.9, 1, 1), 30}, Case{Vec4(-300, 200, -1, 2), 100},
                        Case{Vec4(103, -46, 0.5, -0.2), 2}, Case{Vec4(500, 300, 3, -2), 0}}) {
    const Row4 H = batch_bearing_jacobian(c.theta, c.dt, obs);
    auto h = [&](const Vec4& th) { return bearing(cv_transition(c.dt) * th, obs); };
    for (int i = 0; i < 4; ++i) {
      const double step = 1e-4;
      Vec4 p = c.theta, m = c.theta;
      p[i] += step;
      m[i] -= step;
      const double fd = wrap_pi(h(p) - h(m)) / (2 * step);
      INFO("theta " << c.theta.transpose() << " dt " << c.dt << " component " << i);
      CHECK(H(i) == Approx(fd).margin(1e-9).epsilon(1e-6));
    }
  }
}

TEST_CASE("ml: information, gradient and cost agree with their definitions", "[tma][ml]") {
  TmaOptions o;
  o.add_nav_noise = false;  // R constant: g is exactly -1/2 the gradient of the cost
  Flight f;
  f.duration_s = 40;  // part of an orbit
  Rng rng(7, 0, Stream::kTest);
  const auto zs = simulate(f, rng);
  // A decrement tolerance no solution misses: theta stays at the prior mean (600 m out on the
  // first bearing, the truth at 300 m), far from the optimum, with A and g summed there.
  BatchMl ml(o, BatchMlSettings{1, 1e300});
  for (const auto& z : zs) ml.process(z);
  REQUIRE(ml.passes() == 0);
  REQUIRE(ml.newton_decrement() > 100);
  const Vec4 th = ml.reference_state();
  // The information recomputed from its definition with the analytic Jacobian: the prior's
  // information (the EKF's initial covariance inverted) plus sum H^T H / R over bearings 2..N.
  CartesianEkf prior(o, o.range_prior_m, o.range_sigma_m);
  prior.process(zs.front());
  Mat4 A = prior.estimate().P.inverse();
  for (std::size_t k = 1; k < zs.size(); ++k) {
    const Row4 H = batch_bearing_jacobian(th, zs[k].t_s - zs.front().t_s, zs[k].p_obs_F);
    A += H.transpose() * H / (zs[k].sigma_rad * zs[k].sigma_rad);
  }
  CHECK((ml.information() - A).norm() <= 1e-9 * A.norm());
  // The gradient against central differences of the cost (relative steps).
  for (int i = 0; i < 4; ++i) {
    const double step = i < 2 ? 1e-3 : 1e-5;
    Vec4 p = th, m = th;
    p[i] += step;
    m[i] -= step;
    const double fd = (ml.cost(p) - ml.cost(m)) / (2 * step);
    INFO("component " << i << " g " << ml.gradient()[i] << " fd " << fd);
    CHECK(-2 * ml.gradient()[i] == Approx(fd).epsilon(1e-6));
  }
  // Refining lowers the cost and drives the Newton decrement to zero.
  const double c0 = ml.cost(th);
  ml.refine(100, 1e-14);
  CHECK(ml.cost(ml.reference_state()) <= c0);
  CHECK(ml.newton_decrement() < 1e-12);
}

TEST_CASE("ml: the warm-started per-bearing solution equals the fully converged batch solution",
          "[tma][ml]") {
  TmaOptions o;
  Flight f;
  Rng rng(11, 0, Stream::kTest);
  const auto zs = simulate(f, rng);
  BatchMl ml(o);
  double worst = 0;  // [sigma] largest distance of the per-bearing solution from the optimum
  for (std::size_t k = 0; k < zs.size(); ++k) {
    ml.process(zs[k]);
    if (k % 25 != 0 && k + 1 != zs.size()) continue;
    BatchMl full = ml;
    full.refine(200, 1e-18);
    const Vec4 d = ml.reference_state() - full.reference_state();
    worst = std::max(worst, std::sqrt(d.dot(full.information() * d)));
  }
  INFO("largest distance from the converged solution: " << worst << " sigma");
  // decrement_tol = 1e-4 keeps theta within about sqrt(1e-4) = 0.01 sigma of the optimum of its
  // quadratic model; allow 0.05 sigma for the model's own error while the estimate still moves.
  CHECK(worst < 0.05);
  // Work: warm-started, about one pass over the data per bearing (measured 1.07 here), far
  // below the limit of max_trials = 8; a cold start or a damping stuck high would need several.
  INFO("passes " << ml.passes() << " for " << zs.size() << " bearings");
  CHECK(ml.passes() < 2 * static_cast<long>(zs.size()));
}

TEST_CASE("ml: the error at the end of a well-observed flight matches the batch's own Fisher "
          "covariance (mean NEES in the chi-square band)", "[tma][ml][ensemble]") {
  // One orbit of radius 300 m at 20 m/s about a 1 m/s object, bearings at 2 Hz (189 of them):
  // range is observable, the posterior is nearly Gaussian, the prior (600 +- 400 m, truth 300 m)
  // weighs about 1e-6 of the data. Then the MAP estimate's error e at the end is close to
  // N(0, A^-1) and e^T A e ~ chi2(4) per run; the runs are independent, so the sum of N of them
  // is chi2(4 N) and the mean NEES lies in chi2(4 N) / N's two-sided 95 % band (for N = 300:
  // about 3.69-4.33) unless the covariance is wrong.
  TmaOptions o;
  Flight f;
  f.period_s = 0.5;
  const long N = 300;
  double sum = 0, sum_half = 0, sum_double = 0, pos2 = 0, sigma2 = 0;
  for (long r = 0; r < N; ++r) {
    Rng rng(2025, static_cast<std::uint64_t>(r), Stream::kTest);
    const auto zs = simulate(f, rng);
    BatchMl ml(o);
    for (const auto& z : zs) ml.process(z);
    const Gaussian g = ml.estimate();
    const Vec4 truth = cv_transition(zs.back().t_s) * f.x0;
    const double q = nees(g, truth);
    sum += q;
    sum_half += 2 * q;   // the same error against the covariance halved
    sum_double += q / 2;  // ... and doubled
    pos2 += (g.x - truth).head<2>().squaredNorm();
    sigma2 += g.P(kN, kN) + g.P(kE, kE);
  }
  const auto band = chi2_mean_band(N, 4, 1.959963984540054);
  INFO("mean NEES " << sum / N << " band [" << band.first << ", " << band.second << "], position RMSE "
                    << std::sqrt(pos2 / N) << " m, mean own sigma " << std::sqrt(sigma2 / N) << " m");
  CHECK(sum / N >= band.first);
  CHECK(sum / N <= band.second);
  // The test can fail: a covariance wrong by a factor 2 either way falls outside the band.
  CHECK(sum_half / N > band.second);
  CHECK(sum_double / N < band.first);
}

namespace {
struct EnsembleResult {
  double ekf_rmse = 0, ekf_nees = 0, ml_rmse = 0, ml_nees = 0;
  long ekf_over = 0, ml_over = 0;  // runs with NEES above chi2(4)'s 99.9 % quantile 18.47
};
EnsembleResult run_pair(const Flight& f, const TmaOptions& o, long N, std::uint64_t seed) {
  EnsembleResult res;
  for (long r = 0; r < N; ++r) {
    Rng rng(seed, static_cast<std::uint64_t>(r), Stream::kTest);
    const auto zs = simulate(f, rng);
    BatchMl ml(o);
    CartesianEkf ekf(o, o.range_prior_m, o.range_sigma_m);
    for (const auto& z : zs) {
      ml.process(z);
      ekf.process(z);
    }
    const Vec4 truth = cv_transition(zs.back().t_s) * f.x0;
    const double qm = nees(ml.estimate(), truth), qe = nees(ekf.estimate(), truth);
    res.ml_rmse += (ml.estimate().x - truth).head<2>().squaredNorm();
    res.ekf_rmse += (ekf.estimate().x - truth).head<2>().squaredNorm();
    res.ml_nees += qm;
    res.ekf_nees += qe;
    res.ml_over += qm > 18.47;
    res.ekf_over += qe > 18.47;
  }
  res.ml_rmse = std::sqrt(res.ml_rmse / N);
  res.ekf_rmse = std::sqrt(res.ekf_rmse / N);
  res.ml_nees /= N;
  res.ekf_nees /= N;
  return res;
}
}  // namespace

TEST_CASE("ml: from a wrong range prior the batch converges where the single EKF is over-confident",
          "[tma][ml][ensemble]") {
  // Half an orbit of radius 300 m (47 s at 5 Hz) with the range prior 2000 +- 1500 m, the truth
  // at 300 m: the single EKF linearises its first updates near 2000 m and its covariance
  // collapses before the range is known; the batch re-linearises every bearing at each new
  // solution. Measured (seed 31, 100 runs): EKF position RMSE 316 m, mean NEES 7.8e4, 31 runs
  // above chi2(4)'s 99.9 % quantile; batch 1.79 m (PCRB 1.62 m), mean NEES 4.28, none above.
  // Asserted with wide margins only.
  TmaOptions o;
  o.range_prior_m = 2000;
  o.range_sigma_m = 1500;
  Flight f;
  f.duration_s = 0.5 * 2 * M_PI * f.radius_m / f.speed_mps;
  const long N = 100;
  const auto r = run_pair(f, o, N, 31);
  const double pcrb = pcrb_pos_end(f, o);
  INFO("EKF: RMSE " << r.ekf_rmse << " m, mean NEES " << r.ekf_nees << ", " << r.ekf_over
                    << " runs above chi2(4) 99.9 %; ML: RMSE " << r.ml_rmse << " m (PCRB " << pcrb
                    << " m), mean NEES " << r.ml_nees << ", " << r.ml_over << " runs above");
  CHECK(r.ekf_nees > 100);      // the EKF: over-confident (chi2(4) has mean 4)
  CHECK(r.ekf_over >= 10);      // ... in many runs, not one
  CHECK(r.ml_rmse < 0.1 * r.ekf_rmse);
  // Efficient: for 100 runs RMSE^2 has a relative standard error of about 1/sqrt(100) = 10 %
  // (5 % in RMSE); 1.25 is 5 standard errors above the bound, 0.8 four below.
  CHECK(r.ml_rmse / pcrb < 1.25);
  CHECK(r.ml_rmse / pcrb > 0.8);
  const auto band = chi2_mean_band(N, 4, 3.2905267314918945);  // 99.9 %
  CHECK(r.ml_nees > band.first);
  CHECK(r.ml_nees < band.second);
  CHECK(r.ml_over <= 3);  // a quantile that 0.1 % of runs exceed: at most 3 of 100 allowed
}

TEST_CASE("tma.estimators: selects the estimators in order, bad entries are errors naming the key",
          "[tma][ml][config]") {
  const auto load = [](const std::string& value) {
    nlohmann::json doc = {{"kind", "uav"}};
    apply_override(doc, "tma.estimators=" + value);
    return UavScenario::from_json(doc);
  };
  // The default keeps today's pair, in today's order.
  const UavScenario def = UavScenario::from_json(nlohmann::json{{"kind", "uav"}});
  CHECK(def.tma.estimators == std::vector<std::string>{"ekf", "rpekf"});
  const UavScenario three = load(R"(["ml","ekf","rpekf"])");
  const auto est = make_estimators(three.tma, 1, 0);
  REQUIRE(est.size() == 3);
  CHECK(est[0]->name() == "ml");
  CHECK(est[1]->name() == "ekf");
  CHECK(est[2]->name() == "rpekf");
  // The effective scenario prints the list and reads back the same.
  std::ostringstream printed;
  three.print(printed);
  CHECK(UavScenario::from_json(nlohmann::json::parse(printed.str())).tma.estimators == three.tma.estimators);

  struct Bad {
    std::string value, expect;
  };
  for (const Bad& b : {Bad{R"(["ekf","mll"])", "'mll' is not one of ekf, rpekf, ml, pf (did you mean 'ml'?)"},
                       Bad{R"(["rpkef"])", "did you mean 'rpekf'?"},
                       Bad{R"(["kalman"])", "'kalman' is not one of"},
                       Bad{R"([])", "the list is empty"},
                       Bad{R"(["ekf","ekf"])", "'ekf' is listed twice"},
                       Bad{R"("ml")", "expected a list of strings"},
                       Bad{R"(["ekf",3])", "expected a list of strings, got 3"}}) {
    INFO(b.value);
    try {
      load(b.value);
      FAIL("accepted tma.estimators=" << b.value);
    } catch (const ConfigError& e) {
      const std::string m = e.what();
      CHECK(m.find("scenario key 'tma.estimators'") != std::string::npos);
      CHECK(m.find(b.expect) != std::string::npos);
    }
  }
  // Closed-loop guidance needs its estimator to run.
  nlohmann::json loop = {{"kind", "uav"}};
  apply_override(loop, "uav.guidance=los");
  apply_override(loop, R"(tma.estimators=["ekf","ml"])");
  CHECK_THROWS_WITH(UavScenario::from_json(loop),
                    Catch::Contains("'uav.guidance_estimator' = \"rpekf\" is not among tma.estimators"));
  apply_override(loop, "uav.guidance_estimator=ml");
  CHECK(UavScenario::from_json(loop).uav.guidance_estimator == "ml");
  // A misspelt key is named too (the section's did-you-mean).
  nlohmann::json doc = {{"kind", "uav"}};
  apply_override(doc, R"(tma.estimator=["ml"])");
  CHECK_THROWS_WITH(UavScenario::from_json(doc), Catch::Contains("tma.estimator (did you mean 'tma.estimators'?)"));
}
