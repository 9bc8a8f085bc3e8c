// Tests of ReplayTrajectory (sim/trajectory/replay_trajectory.hpp) and of the replay scenario
// through the whole chain in one process.
#include "sim/trajectory/approach_trajectory.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "sim/trajectory/replay_trajectory.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("rnav_test_replay_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The default analytic approach sampled every `dt` s as a replay CSV (WGS84 through L).
std::string write_analytic_csv(const fs::path& file, const Scenario& sc, double dt) {
  const ApproachTrajectory tr(sc.trajectory);
  const LocalLevelFrame L = sc.landing_frame();
  std::ofstream o(file);
  o << "t_s,lat_deg,lon_deg,h_m\n" << std::fixed;
  for (double t = 0; t <= tr.duration_s(); t += dt) {
    const Geodetic g = L.to_geodetic(tr.at(t).p_TA_L);
    o << std::setprecision(3) << t << "," << std::setprecision(11) << g.lat_deg << "," << g.lon_deg
      << "," << std::setprecision(6) << g.h_m << "\n";
  }
  return file.string();
}

std::string error_of(const fs::path& file, double smoothing_s = 30, double max_gap_s = 15) {
  try {
    ReplayTrajectory(file.string(), Scenario{}.landing_frame(), smoothing_s, max_gap_s);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("smoother weights reproduce quadratics (the basis of every bound below)", "[replay]") {
  const Scenario sc;
  const fs::path d = scratch("weights");
  const ReplayTrajectory r(write_analytic_csv(d / "a.csv", sc, 5.0), sc.landing_frame(), 30, 15);
  for (double t : {0.0, 1.3, 52.7, 250.0, r.duration_s() - 0.4, r.duration_s()}) {
    const auto w = r.weights(t);
    double s0 = 0, s1 = 0, s2 = 0, d0 = 0, d1 = 0, d2 = 0;
    for (std::size_t k = 0; k < w.l.size(); ++k) {
      const double tau = r.sample_time_s(w.first + k) - t;
      s0 += w.l[k], s1 += w.l[k] * tau, s2 += w.l[k] * tau * tau;
      d0 += w.d[k], d1 += w.d[k] * tau, d2 += w.d[k] * tau * tau;
    }
    CHECK(w.l.size() >= 3);
    CHECK(s0 == Approx(1).margin(1e-12));
    CHECK(s1 == Approx(0).margin(1e-10));
    CHECK(s2 == Approx(0).margin(1e-8));
    CHECK(d0 == Approx(0).margin(1e-12));
    CHECK(d1 == Approx(1).margin(1e-12));
    CHECK(d2 == Approx(0).margin(1e-10));
  }
}

TEST_CASE("replay of the analytic approach sampled at 5 s: exact on straight legs, bounded in turns",
          "[replay]") {
  Scenario sc;
  const fs::path d = scratch("analytic");
  const double W = 30;
  const ApproachTrajectory tr(sc.trajectory);
  const ReplayTrajectory r(write_analytic_csv(d / "a.csv", sc, 5.0), sc.landing_frame(), W, 15);
  CHECK(r.duration_s() == Approx(std::floor(tr.duration_s() / 5) * 5));
  // Kinks of the analytic path (acceleration jumps): turn start/end, start of the descent.
  const double t_turn_end = tr.final_time_s();
  const double t_turn_start = t_turn_end - tr.turn_radius_m() * std::acos(-(Eigen::Vector2d(27000 - 30860, -9860).normalized().x())) / 75.0;
  const double t_desc = t_turn_end + (tr.at(t_turn_end).p_TA_L.x() - tr.descent_x_m()) / 75.0;
  double max_p_straight = 0, max_v_straight = 0, max_p = 0, max_v = 0;
  long n_straight = 0, bad = 0;
  for (double t = 0; t <= r.duration_s(); t += 0.25) {
    const AircraftKinematics k = r.at(t), truth = tr.at(t);
    const double ep = (k.p_TA_L - truth.p_TA_L).norm(), ev = (k.v_A_L - truth.v_A_L).norm();
    max_p = std::max(max_p, ep), max_v = std::max(max_v, ev);
    const bool straight = std::abs(t - t_turn_start) >= W && std::abs(t - t_turn_end) >= W && std::abs(t - t_desc) >= W;
    if (straight) {
      // A local quadratic reproduces a path linear in t exactly: what is left is the CSV's
      // rounding (1e-11 deg ~ 1 um, 1e-6 m) times sum |l_i| (< 2): bound 1 mm and 1 mm/s.
      ++n_straight;
      max_p_straight = std::max(max_p_straight, ep), max_v_straight = std::max(max_v_straight, ev);
      if (ep > 1e-3 || ev > 1e-3) ++bad;
      continue;
    }
    // Near a kink the fit's error is sum_i l_i (p_i - q(t_i)) for ANY quadratic q (the weights
    // reproduce quadratics), so with q = the second-order Taylor polynomial of the truth at t
    // (acceleration by central difference): |error| <= sum|l_i| max_i |p_i - q(t_i)|, and the
    // same with the velocity weights d_i for the velocity (q'(t) = v(t)). Plus 1 mm rounding.
    const Eigen::Vector3d a = (tr.at(t + 1e-3).v_A_L - tr.at(t - 1e-3).v_A_L) / 2e-3;
    const auto w = r.weights(t);
    double L1 = 0, D1 = 0, dev = 0;
    for (std::size_t i = 0; i < w.l.size(); ++i) {
      const double tau = r.sample_time_s(w.first + i) - t;
      const Eigen::Vector3d q = truth.p_TA_L + truth.v_A_L * tau + 0.5 * a * tau * tau;
      dev = std::max(dev, (tr.at(r.sample_time_s(w.first + i)).p_TA_L - q).norm());
      L1 += std::abs(w.l[i]), D1 += std::abs(w.d[i]);
    }
    if (ep > L1 * dev + 1e-3 || ev > D1 * dev + 1e-3) ++bad;
  }
  WARN("analytic replay, W = 30 s, 5 s samples: straight legs max |dp| = " << max_p_straight
       << " m, |dv| = " << max_v_straight << " m/s; overall max |dp| = " << max_p << " m, |dv| = " << max_v << " m/s");
  CHECK(n_straight > 1000);
  CHECK(bad == 0);
}

TEST_CASE("replay velocity is the derivative of its position, and both are continuous", "[replay]") {
  const Scenario sc;
  const fs::path d = scratch("fd");
  const ReplayTrajectory r(write_analytic_csv(d / "a.csv", sc, 5.0), sc.landing_frame(), 30, 15);
  // Central difference error h^2/6 |p'''|: the smoothed path's jerk is at most the 4.6 m/s^2
  // acceleration step of the turn spread over the window, ~ 4.6 / W x (a kernel factor < 3)
  // = 0.5 m/s^3, so with h = 0.01 s the error is < 1e-5 m/s; rounding of 3e4 m coordinates
  // adds ~1e-12 m / 0.02 s. Bound: 1e-4 m/s.
  const double h = 0.01;
  long bad = 0, n = 0;
  double max_jump = 0;
  AircraftKinematics prev = r.at(h);
  for (double t = h; t <= r.duration_s() - h; t += 0.05, ++n) {
    const AircraftKinematics k = r.at(t);
    const Eigen::Vector3d fd = (r.at(t + h).p_TA_L - r.at(t - h).p_TA_L) / (2 * h);
    if ((fd - k.v_A_L).norm() > 1e-4) {
      ++bad;
      if (bad < 4) WARN("t=" << t << " fd " << fd.transpose() << " v " << k.v_A_L.transpose());
    }
    max_jump = std::max(max_jump, (k.v_A_L - prev.v_A_L).norm());
    prev = k;
  }
  CHECK(n > 5000);
  CHECK(bad == 0);
  // Continuity: over 0.05 s the velocity changes by at most (max acceleration) x 0.05 s; the
  // analytic path's largest acceleration is V^2 / r = 4.6 m/s^2 and smoothing only lowers it
  // (x sum|l_i| < 2 at most): 0.46 m/s. A jump when a sample enters the window would break it.
  CHECK(max_jump < 0.46);
  // Clamped outside [0, duration].
  CHECK((r.at(-10).p_TA_L - r.at(0).p_TA_L).norm() == 0);
  CHECK((r.at(r.duration_s() + 10).v_A_L - r.at(r.duration_s()).v_A_L).norm() == 0);
}

TEST_CASE("bad replay CSV: errors name file and line", "[replay][input]") {
  const fs::path d = scratch("bad");
  const std::string head = "t_s,lat_deg,lon_deg,h_m\n";
  const std::string ok = "0,48.2,16.7,900\n5,48.19,16.71,890\n10,48.18,16.72,880\n15,48.17,16.73,870\n";
  std::ofstream(d / "ok.csv") << head << ok;
  CHECK(error_of(d / "ok.csv").empty());
  std::ofstream(d / "nan.csv") << head << "0,48.2,16.7,900\n5,48.19,16.71,nan\n10,48.18,16.72,880\n";
  CHECK_THAT(error_of(d / "nan.csv"), Catch::Contains("nan.csv:3") && Catch::Contains("h_m"));
  std::ofstream(d / "order.csv") << head << "0,48.2,16.7,900\n5,48.19,16.71,890\n5,48.18,16.72,880\n";
  CHECK_THAT(error_of(d / "order.csv"), Catch::Contains("order.csv:4") && Catch::Contains("time order"));
  std::ofstream(d / "gap.csv") << head << "0,48.2,16.7,900\n5,48.19,16.71,890\n25,48.18,16.72,880\n30,48.17,16.73,870\n";
  CHECK_THAT(error_of(d / "gap.csv"), Catch::Contains("gap.csv:4") && Catch::Contains("replay_max_gap_s"));
  CHECK_THAT(error_of(d / "ok.csv", 9), Catch::Contains("replay_smoothing_s"));
  std::ofstream(d / "lat.csv") << head << "0,98.2,16.7,900\n5,48.19,16.71,890\n10,48.18,16.72,880\n";
  CHECK_THAT(error_of(d / "lat.csv"), Catch::Contains("lat.csv:2") && Catch::Contains("lat_deg"));
  std::ofstream(d / "cols.csv") << "t_s,lat_deg,lon_deg\n0,48.2,16.7\n";
  CHECK_THAT(error_of(d / "cols.csv"), Catch::Contains("cols.csv:1") && Catch::Contains("h_m"));
  std::ofstream(d / "short.csv") << head << "0,48.2,16.7,900\n5,48.19,16.71,890\n";
  CHECK_THAT(error_of(d / "short.csv"), Catch::Contains("short.csv") && Catch::Contains("at least 3"));
  CHECK_THAT(error_of(d / "absent.csv"), Catch::Contains("absent.csv"));
}

TEST_CASE("replay_csv resolves against the scenario file's directory and overrides against the cwd",
          "[replay][config]") {
  const fs::path d = scratch("paths");
  fs::create_directories(d / "sub");
  std::ofstream(d / "sub" / "s.json") << R"({"trajectory": {"replay_csv": "r.csv"}})";
  const Scenario sc = Scenario::load((d / "sub" / "s.json").string());
  CHECK(sc.trajectory.replay_csv == (d / "sub" / "r.csv").string());
  const Scenario so = Scenario::load((d / "sub" / "s.json").string(), {"trajectory.replay_csv=x/r.csv"});
  CHECK(so.trajectory.replay_csv == (fs::current_path() / "x" / "r.csv").string());
  CHECK_THROWS_WITH(Scenario::load((d / "sub" / "s.json").string(), {"trajectory.replay_csv=5"}),
                    Catch::Contains("trajectory.replay_csv"));
}

TEST_CASE("the shipped Vienna replay scenario runs through the whole chain", "[replay][ensemble]") {
  const std::string file = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/vienna_replay.json";
  const Scenario sc = Scenario::load(file);
  const auto traj = make_trajectory(sc.trajectory, sc.site());
  REQUIRE(dynamic_cast<const ReplayTrajectory*>(traj.get()) != nullptr);
  // The exported approach ends at its last point before the threshold (x >= 0), on the
  // glide path: within the last 5 s step (< 500 m) and tens of metres up.
  const auto end = traj->at(traj->duration_s());
  CHECK(end.p_TA_L.x() > 0);
  CHECK(end.p_TA_L.x() < 500);
  CHECK(end.p_TA_L.y() > 0);
  CHECK(std::abs(end.p_TA_L.z()) < 30);
  const fs::path out = scratch("ensemble");
  const auto r = run_inproc_ensemble(sc, 3, 1, out.string());
  INFO(r.failure);
  REQUIRE(r.exit_code == 0);
  std::ifstream f(out / "table2_detail.json");
  REQUIRE(f.good());
  const auto j = nlohmann::json::parse(f);
  for (const char* range : {"12000", "4000"}) {
    CHECK(j["APOI"][range]["plots_per_realization"].get<int>() >= 3);
    CHECK(j["TOI"][range]["plots_per_realization"].get<int>() >= 3);
  }
  CHECK(fs::exists(out / "stats_time.csv"));
}
