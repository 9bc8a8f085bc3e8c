// Azimuth-only diagnosis: effects hidden in synthetic bearings are found; the real Autoferry
// camera data shows its excess, correlated noise; bad CSV input names file and line.
#include <catch2/catch.hpp>

#include "azimuth_data.hpp"
#include "config.hpp"
#include "random.hpp"
#include "uav_diagnose.hpp"

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

// An observer circling (R = 300 m, 20 m/s) a boat at 1 m/s; bearings at 5 Hz with
// sigma 0.5 deg, plus a hidden bias [rad] and time offset tau [s] (stamp minus true time).
AzimuthData synthetic(double bias, double tau, std::uint64_t seed) {
  const LocalLevelFrame F({63.44, 10.4, 0}, 0.0);
  Rng rng(seed, 0, Stream::kTest);
  AzimuthData d;
  auto target = [](double t) { return Eigen::Vector2d(0.7 * t, 0.7 * t); };
  auto observer = [](double t) {
    const double th = M_PI - 20.0 * t / 300.0;
    return Eigen::Vector2d(300 * std::cos(th), 300 * std::sin(th));
  };
  for (int k = 0; k <= 1000; ++k) {
    const double t = 0.2 * k;
    const Eigen::Vector2d o = observer(t), p = target(t);
    auto geo = [&](const Eigen::Vector2d& q) { return F.to_geodetic(Eigen::Vector3d(q.x(), 0, q.y())); };
    d.observer.push_back({t, geo(o)});
    d.truth.push_back({t, geo(p)});
    // the frame stamped t shows the geometry of t - tau
    const Eigen::Vector2d os = observer(t - tau), ps = target(t - tau);
    const double b = std::atan2(ps.y() - os.y(), ps.x() - os.x()) + bias + 0.5 * kDegToRad * rng.normal();
    d.frames.push_back({t, {wrap_pi(b)}});
  }
  return d;
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
    CHECK(r.gain.at("bearing_rad").extended_rms < r.gain.at("bearing_rad").nominal_rms);
  }
  SECTION("time offset") {
    const auto r = diagnose_uav(synthetic(0, 0.3, 43), {});
    const auto* e = find(r, "bearing_time_offset");
    REQUIRE(e != nullptr);
    CHECK(std::abs(e->estimate[0] - 0.3) <= 3 * e->stderr_[0]);
    CHECK(r.gain.at("bearing_rad").extended_rms < r.gain.at("bearing_rad").nominal_rms);
  }
}

TEST_CASE("uav diagnose on the real Autoferry EO bearings: noise far above nominal and correlated",
          "[diagnose][uav][real]") {
  const std::string sc = std::string(RNAV_SOURCE_DIR) + "/../shared/data/autoferry/scenario4";
  if (!fs::exists(sc)) {
    WARN("shared data not found at " << sc << ": skipped");
    return;
  }
  const fs::path out = fs::temp_directory_path() / "rnav_af4";
  const std::string cmd = std::string(RNAV_BINARY_DIR) + "/bin/rnav_import_autoferry " + sc +
                          " --sensor eo --target 1 --out " + out.string() + " 2>/dev/null";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const auto r = diagnose_uav(AzimuthData::read_folder(out.string()), {});
  INFO(r.text());
  const auto* ns = find(r, "noise_scale");
  REQUIRE(ns != nullptr);
  CHECK(ns->estimate[0] - 3 * ns->stderr_[0] > 1.5);  // at least 1.5x the nominal 0.5 deg
  CHECK(find(r, "correlated_noise") != nullptr);
}

TEST_CASE("azimuth CSV: bad input names file and line", "[diagnose][uav][input]") {
  const fs::path d = fs::temp_directory_path() / "rnav_az_bad";
  synthetic(0, 0, 1).write_folder(d.string());
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
