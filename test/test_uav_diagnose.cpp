// Azimuth-only diagnosis: effects hidden in synthetic bearings are found; the real Autoferry
// camera data shows its excess, correlated noise; bad CSV input names file and line.
#include <catch2/catch.hpp>

#include "estimators/diagnosis/azimuth_data.hpp"
#include "sim/uav/bearing_error_model.hpp"
#include "common/io/config.hpp"
#include "test/csv_units.hpp"
#include "common/physics/random.hpp"

#include <cmath>
#include "estimators/diagnosis/uav_diagnose.hpp"
#include "estimators/diagnosis/uav_track_fit.hpp"

#include <filesystem>
#include <functional>
#include <fstream>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

// What the synthetic data hides.
struct Hidden {
  double bias = 0;          // [rad] bearing bias
  double tau = 0;           // [s] time offset (stamp minus true time)
  double man_t = -1;        // [s] manoeuvre time (-1: none)
  Eigen::Vector2d dv = Eigen::Vector2d::Zero();  // [m/s] velocity change (north, east) at man_t
  double clutter = 0;       // probability of an extra, uniformly random detection per frame
  double noise_scale = 1;   // multiplies the 0.5 deg noise sigma
  double corr_tau = 0;      // [s] the noise as a Gauss-Markov process with this correlation time (0: white)
  double outlier_prob = 0;  // probability per frame of an extra N(0, (10 sigma)^2) error
  /// The simulator's own deterministic sensor errors (sim/uav's SystematicBearingError: the
  /// catalogue's columns), added to each bearing; all off by default.
  SensorEffectsOptions sim_effects;
};

// An observer circling (R = 300 m, 20 m/s) a boat at 1 m/s; bearings at 5 Hz for 200 s with
// sigma 0.5 deg, plus what h hides.
AzimuthData synthetic(const Hidden& h, std::uint64_t seed) {
  const LocalLevelFrame F({63.44, 10.4, 0}, 0.0);
  Rng rng(seed, 0, Stream::kTest);
  AzimuthData d;
  auto target = [&](double t) {
    Eigen::Vector2d p(0.7 * t, 0.7 * t);
    if (h.man_t >= 0 && t > h.man_t) p += h.dv * (t - h.man_t);
    return p;
  };
  auto observer = [](double t) {
    const double th = M_PI - 20.0 * t / 300.0;
    return Eigen::Vector2d(300 * std::cos(th), 300 * std::sin(th));
  };
  const double sigma = 0.5 * kDegToRad * h.noise_scale;
  GaussMarkov gm(sigma, h.corr_tau > 0 ? h.corr_tau : 1.0);
  gm.start(rng);
  for (int k = 0; k <= 1000; ++k) {
    const double t = 0.2 * k;
    const Eigen::Vector2d o = observer(t), p = target(t);
    const double n1 = rng.normal(), n2 = rng.normal(), u1 = rng.uniform();
    double noise = h.corr_tau > 0 ? (k ? gm.step(0.2, rng) : gm.value()) : sigma * n1;
    if (u1 < h.outlier_prob) noise += 10 * sigma * n2;
    auto geo = [&](const Eigen::Vector2d& q) { return F.to_geodetic(Eigen::Vector3d(q.x(), 0, q.y())); };
    d.observer.push_back({t, geo(o)});
    d.truth.push_back({t, geo(p)});
    // the frame stamped t shows the geometry of t - tau
    const Eigen::Vector2d os = observer(t - h.tau), ps = target(t - h.tau);
    double b = std::atan2(ps.y() - os.y(), ps.x() - os.x()) + h.bias + noise;
    {
      // the true bearing's rate by a central difference, for the simulator's error model
      auto bearing = [&](double s) {
        const Eigen::Vector2d q = target(s) - observer(s);
        return std::atan2(q.y(), q.x());
      };
      const double rate = wrap_pi(bearing(t + 1e-3) - bearing(t - 1e-3)) / 2e-3;
      b += SystematicBearingError(h.sim_effects).error({t, bearing(t), (p - o).norm(), rate}, rng);
    }
    BearingFrame fr{t, {wrap_pi(b)}};
    const double u = rng.uniform(), c = rng.uniform();
    if (u < h.clutter) fr.bearings_rad.push_back(wrap_pi(2 * M_PI * c));
    d.frames.push_back(fr);
  }
  return d;
}

AzimuthData synthetic(double bias, double tau, std::uint64_t seed) {
  Hidden h;
  h.bias = bias;
  h.tau = tau;
  return synthetic(h, seed);
}

UavDiagnoseOptions no_truth() {
  UavDiagnoseOptions o;
  o.ignore_truth = true;
  return o;
}

const EffectResult* find(const DiagnoseReport& r, const std::string& n) {
  for (const auto& e : r.effects)
    if (e.name == n) return &e;
  return nullptr;
}

}  // namespace

TEST_CASE("uav diagnose: nominal synthetic bearings raise no effect", "[diagnose][uav]") {
  int alarms = 0;
  for (std::uint64_t s = 1; s <= 10; ++s) alarms += !diagnose_uav(synthetic(0, 0, s), {}).effects.empty();
  // familywise alpha = 0.01 per data set: P(>= 2 alarms in 10) = 0.004
  CHECK(alarms <= 1);
}

TEST_CASE("uav diagnose: a hidden bearing bias and a hidden time offset are found", "[diagnose][uav]") {
  SECTION("bias") {
    const auto r = diagnose_uav(synthetic(0.2 * kDegToRad, 0, 42), {});
    const auto* e = find(r, "bearing_bias");
    REQUIRE(e != nullptr);
    CHECK(std::abs(e->estimate[0] - 0.2 * kDegToRad) <= 3 * e->stderr_[0]);
    CHECK(r.gain.at("bearing").extended_rms < r.gain.at("bearing").nominal_rms);
  }
  SECTION("time offset") {
    const auto r = diagnose_uav(synthetic(0, 0.3, 43), {});
    const auto* e = find(r, "time_offset");
    REQUIRE(e != nullptr);
    CHECK(std::abs(e->estimate[0] - 0.3) <= 3 * e->stderr_[0]);
    CHECK(r.gain.at("bearing").extended_rms < r.gain.at("bearing").nominal_rms);
  }
}

TEST_CASE("uav diagnose on the real Autoferry EO bearings: noise far above nominal and correlated",
          "[diagnose][uav][real]") {
  const std::string sc = std::string(RNAV_DATA_DIR) + "/autoferry/scenario4";
  REQUIRE(fs::exists(sc));  // the recordings are part of the repository (test/data)
  const fs::path out = fs::temp_directory_path() / "rnav_af4";
  fs::remove_all(out);  // (the importer refuses a folder that is not its own output)
  const std::string cmd = std::string(RNAV_BINARY_DIR) + "/bin/rnav_import_autoferry " + sc +
                          " --sensor eo --target 1 --out " + out.string() + " 2>/dev/null";
  REQUIRE(std::system(cmd.c_str()) == 0);
  int n_csv = 0;
  CHECK(rnav_test::csv_folder_units_problems(out, &n_csv) == "");  // observer, bearings, truth
  CHECK(n_csv == 3);
  const auto r = diagnose_uav(AzimuthData::read_folder(out.string()), {});
  INFO(r.text());
  const auto* ns = find(r, "noise_scale");
  REQUIRE(ns != nullptr);
  // well above the nominal 0.5 deg (robust estimate: a fifth of the frames miss the 4 deg gate)
  // named at the familywise level (its adjusted p below alpha = 0.01: the test is the chi-square
  // of the variance ratio with the effective sample size of correlated noise, not +-3 SE on the
  // skewed ratio), and at least twice the nominal sigma
  CHECK(ns->log10_p < -2);
  CHECK(ns->estimate[0] > 2.0);
  CHECK(find(r, "correlated_noise") != nullptr);
}

TEST_CASE("uav diagnose: each sensor entry the simulator injects is named with its size", "[diagnose][uav]") {
  // One model in one place: the simulator's SystematicBearingError and the diagnosis's catalogue
  // share their columns (common/physics/bearing_effect_columns.hpp). Each entry is hidden alone, through
  // the simulator's error model, at 10-12 standard errors of this geometry (200 s of 5 Hz
  // bearings, sigma 0.5 deg), and must be named with its estimate within 3 SE of the size hidden:
  // the periodic's period (reported first, a grid value: 4 * 1.05^20 s is on the grid) and its
  // sine amplitude.
  struct Case {
    const char* name;
    std::function<void(SensorEffectsOptions&)> set;
    std::vector<double> size;  // the parameters as reported, in order
  };
  const double period = 4 * std::pow(1.05, 20);
  const std::vector<Case> cases = {
      {"bearing_bias", [](SensorEffectsOptions& f) { f.bearing_bias_rad = 0.003; }, {0.003}},
      {"time_offset", [](SensorEffectsOptions& f) { f.time_offset_s = 0.05; }, {0.05}},
      {"bias_drift", [](SensorEffectsOptions& f) { f.bias_drift_radps = 3e-5; }, {3e-5}},
      {"periodic", [period](SensorEffectsOptions& f) { f.periodic_period_s = period, f.periodic_amplitude_rad = 0.004; },
       {period, 0.004}},
  };
  for (const Case& c : cases) {
    Hidden h;
    c.set(h.sim_effects);
    const auto r = diagnose_uav(synthetic(h, 77), {});
    const auto* e = find(r, c.name);
    INFO(c.name);
    REQUIRE(e != nullptr);
    REQUIRE(e->estimate.size() >= c.size.size());
    for (std::size_t i = 0; i < c.size.size(); ++i) {
      INFO("parameter " << i << ": " << e->estimate[i] << " +- " << e->stderr_[i] << ", hidden " << c.size[i]);
      CHECK(std::abs(e->estimate[i] - c.size[i]) <= 3 * e->stderr_[i]);
    }
  }
}

TEST_CASE("azimuth CSV: bad input names file and line", "[diagnose][uav][input]") {
  const fs::path d = fs::temp_directory_path() / "rnav_az_bad";
  fs::remove_all(d);
  synthetic(0, 0, 1).write_folder(d.string());
  // observer.csv, bearings.csv, truth.csv, each with its units.json (which the reader passes over)
  int n_csv = 0;
  CHECK(rnav_test::csv_folder_units_problems(d, &n_csv) == "");
  CHECK(n_csv == 3);
  REQUIRE_NOTHROW(AzimuthData::read_folder(d.string()));
  std::ofstream(d / "bearings.csv") << "t_s,bearing_deg\n0,10\n0.2,abc\n";
  try {
    AzimuthData::read_folder(d.string());
    FAIL("no error");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()).find("bearings.csv:3: column 'bearing_deg'") != std::string::npos);
  }
  std::ofstream(d / "bearings.csv") << "t_s,bearing_deg\n1,10\n0.5,12\n";
  CHECK_THROWS_WITH(AzimuthData::read_folder(d.string()), Catch::Contains("bearings.csv:3"));
}

TEST_CASE("azimuth data: a far position and a truth sample out of time order are named", "[diagnose][uav][input]") {
  const AzimuthData good = synthetic(0, 0, 1);
  REQUIRE(good.truth.size() > 3);
  REQUIRE_NOTHROW(good.validate("good"));
  AzimuthData d = good;
  std::swap(d.observer[5].g.lat_deg, d.observer[5].g.lon_deg);  // a swapped pair: thousands of km off
  CHECK_THROWS_WITH(d.validate("src"), Catch::Contains("src: observer sample 5") && Catch::Contains("the observer's first position"));
  d = good;
  d.observer[2].g.h_m = 1e7;  // far up but in place: the height is named
  CHECK_THROWS_WITH(d.validate("src"), Catch::Contains("src: observer sample 2: height"));
  d = good;
  d.truth[3].t_s = d.truth[1].t_s;
  CHECK_THROWS_WITH(d.validate("src"), Catch::Contains("src: truth sample 3: time") && Catch::Contains("is not after"));
  d = good;
  d.truth[2].g.h_m = NAN;  // the truth's height is not used, so not checked
  CHECK_NOTHROW(d.validate("src"));
}

TEST_CASE("uav diagnose without truth: the fitted track is the truth's within its covariance",
          "[diagnose][uav][notruth]") {
  // With half the frames carrying a random clutter detection, the RANSAC-initialised CV fit
  // must find the object: its position at t_ref within 3 sigma of its covariance per axis.
  Hidden h;
  h.clutter = 0.5;
  const auto d = synthetic(h, 7);
  const LocalLevelFrame F(d.observer.front().g, 0.0);
  const auto obs = track_observations(d, F);
  const auto f = fit_cv_track(obs, -1e9, 1e9, {});
  const Eigen::Vector2d p_true = Eigen::Vector2d(0.7, 0.7) * f.track.t_ref_s + Eigen::Vector2d(300, 0);
  for (int a = 0; a < 2; ++a) CHECK(std::abs(f.track.p0_F(a) - p_true(a)) < 3 * std::sqrt(f.cov(a, a)));
  for (int a = 0; a < 2; ++a) CHECK(std::abs(f.track.v_F(a) - 0.7) < 3 * std::sqrt(f.cov(2 + a, 2 + a)));
  CHECK(f.n_associated >= 990);  // all but the few frames whose noise exceeds the 4 deg gate (8 sigma)
}

TEST_CASE("uav diagnose without truth: the CV track's Jacobian matches finite differences", "[diagnose][uav][notruth]") {
  CvTrack tr;
  tr.p0_F = {120, -40};
  tr.v_F = {0.8, -0.3};
  tr.t_ref_s = 50;
  TrackObs x;
  x.t_s = 80;
  x.o_F = {-100, 200};
  x.vo_F = {5, 12};
  const Eigen::Vector4d J = tr.jacobian(x);
  for (int k = 0; k < 4; ++k) {
    const double e = 1e-6;
    CvTrack a = tr, b = tr;
    (k < 2 ? a.p0_F(k) : a.v_F(k - 2)) += e;
    (k < 2 ? b.p0_F(k) : b.v_F(k - 2)) -= e;
    CHECK(J(k) == Approx((a.bearing(x) - b.bearing(x)) / (2 * e)).epsilon(1e-6));
  }
  // bearing rate against a central difference in time of the bearing (observer moving at vo)
  TrackObs x1 = x, x0 = x;
  x1.t_s += 1e-3, x1.o_F += 1e-3 * x.vo_F;
  x0.t_s -= 1e-3, x0.o_F -= 1e-3 * x.vo_F;
  CHECK(tr.bearing_rate(x) == Approx((tr.bearing(x1) - tr.bearing(x0)) / 2e-3).epsilon(1e-6));
}

TEST_CASE("uav diagnose without truth: nominal data raise no effect", "[diagnose][uav][notruth]") {
  int alarms = 0;
  std::string what;
  for (std::uint64_t s = 1; s <= 10; ++s) {
    const auto r = diagnose_uav(synthetic(Hidden{}, 100 + s), no_truth());
    if (!r.effects.empty()) {
      ++alarms;
      what += r.text();
    }
  }
  INFO(what);
  // familywise alpha = 0.01 per data set: P(>= 2 alarms in 10) = 0.004
  CHECK(alarms <= 1);
}

TEST_CASE("uav diagnose without truth: a hidden bias and a hidden manoeuvre are found", "[diagnose][uav][notruth]") {
  SECTION("bias") {
    // Circling an object that moves slowly, the bearing rate is nearly constant (-V/R), so a
    // bias and a time offset are nearly the same column: either is acceptable if it names the
    // other as confounded; the bias itself must then be within 3 SE.
    const double b = 0.15 * kDegToRad;
    const auto r = diagnose_uav(synthetic(b, 0, 42), no_truth());
    INFO(r.text());
    const auto* e = find(r, "bearing_bias");
    if (e) {
      CHECK(std::abs(e->estimate[0] - b) <= 3 * e->stderr_[0]);
    } else {
      e = find(r, "time_offset");
      REQUIRE(e != nullptr);
      CHECK(std::find(e->confounded_with.begin(), e->confounded_with.end(), "bearing_bias") != e->confounded_with.end());
    }
    CHECK(r.gain.at("bearing").extended_rms < r.gain.at("bearing").nominal_rms);
    CHECK(r.gain.at("truth_position_m").extended_rms < r.gain.at("truth_position_m").nominal_rms);
  }
  SECTION("manoeuvre") {
    Hidden h;
    h.man_t = 60;
    h.dv = {0.3, -0.3};
    const auto r = diagnose_uav(synthetic(h, 43), no_truth());
    INFO(r.text());
    const auto* e = find(r, "target_maneuver");
    REQUIRE(e != nullptr);
    CHECK(std::abs(e->estimate[0] - 60) <= 2 * e->stderr_[0]);  // within two scan-grid steps
    CHECK(std::abs(e->estimate[1] - 0.3) <= 3 * e->stderr_[1]);
    CHECK(std::abs(e->estimate[2] + 0.3) <= 3 * e->stderr_[2]);
    CHECK(r.gain.at("truth_position_m").extended_rms < r.gain.at("truth_position_m").nominal_rms);
  }
}

namespace {

struct UavCase {
  std::string label;
  Hidden h;
  std::vector<std::pair<std::string, double>> expect;  // name, true value of its first parameter (NaN: not checked)
  bool truth_gain = true;  // the extrapolated track must beat the nominal against truth
};

}  // namespace

TEST_CASE("uav diagnose without truth: each catalogue effect, alone and in pairs, near the detection limit",
          "[diagnose][uav][notruth]") {
  // Detection limits of this geometry (200 s circling, sigma 0.5 deg, alpha 0.01; README):
  // bias 0.95 mrad, time offset 14 ms, manoeuvre 0.03 m/s per component. Hidden magnitudes are
  // 2-4x those, where the test's power is > 0.9 per effect (a miss is a real regression).
  const double nan = std::nan("");
  Hidden bias, offset, man, scale, corr, outl, bias_man, scale_outl, man_corr;
  bias.bias = 0.003;
  offset.tau = 0.05;
  man.man_t = 60, man.dv = {0.15, -0.15};
  scale.noise_scale = 1.6;
  corr.corr_tau = 1.0;
  outl.outlier_prob = 0.02;
  bias_man.bias = 0.003, bias_man.man_t = 60, bias_man.dv = {0.15, -0.15};
  scale_outl.noise_scale = 1.6, scale_outl.outlier_prob = 0.02;
  // Gauss-Markov noise with tau = 1 s at 5 Hz (rho 0.82) inflates the SEs, and with them the
  // limits, by sqrt((1 + rho) / (1 - rho)) = 3.2: the manoeuvre is 0.3 m/s there (2.6x).
  man_corr.man_t = 60, man_corr.dv = {0.3, -0.3}, man_corr.corr_tau = 1.0;
  const std::vector<UavCase> cases = {
      {"bias", bias, {{"bearing_bias", 0.003}}, true},
      {"time_offset", offset, {{"time_offset", 0.05}}, true},
      {"manoeuvre", man, {{"target_maneuver", 60}}, true},
      {"noise_scale", scale, {{"noise_scale", 1.6}}, false},
      {"correlated_noise", corr, {{"correlated_noise", 1.0}}, false},
      {"outliers", outl, {{"outliers", nan}}, false},
      {"bias+manoeuvre", bias_man, {{"bearing_bias", 0.003}, {"target_maneuver", 60}}, true},
      {"noise_scale+outliers", scale_outl, {{"noise_scale", 1.6}, {"outliers", nan}}, false},
      {"manoeuvre+correlated", man_corr, {{"target_maneuver", 60}, {"correlated_noise", 1.0}}, true},
  };
  std::uint64_t seed = 300;
  for (const auto& c : cases) {
    const auto r = diagnose_uav(synthetic(c.h, ++seed), no_truth());
    INFO(c.label << "\n" << r.text());
    bool partner = false;  // a confounded partner was named instead: its extrapolation may be worse
    for (const auto& [name, truth] : c.expect) {
      const EffectResult* e = find(r, name);
      if (!e) {
        // Not named itself: then an effect the report says it cannot be told apart from in
        // this geometry must stand in for it (circling, bias ~ time offset; with a manoeuvre in
        // the model, bias ~ drift).
        for (const auto& x : r.effects)
          if (std::find(x.confounded_with.begin(), x.confounded_with.end(), name) != x.confounded_with.end()) e = &x;
        REQUIRE(e != nullptr);
        partner = true;
        continue;
      }
      REQUIRE(e != nullptr);
      if (std::isnan(truth)) continue;
      // (target_maneuver's first parameter is its time, SE from the profile likelihood)
      CHECK(std::abs(e->estimate[0] - truth) <= 3 * e->stderr_[0]);
    }
    if (c.truth_gain && !partner) CHECK(r.gain.at("truth_position_m").extended_rms < r.gain.at("truth_position_m").nominal_rms);
    // out of sample, the extended model (mean and noise effects) is the likelier one
    CHECK(r.gain.at("bearing").extended_loglik > r.gain.at("bearing").nominal_loglik);
  }
}
