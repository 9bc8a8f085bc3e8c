// Unit tests of sim/trajectory/approach_trajectory.hpp with the default TrajectoryOptions
// (the paper's start point and glide angle plus our documented choices).
#include "sim/trajectory/approach_trajectory.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using rnav::ApproachTrajectory;
using rnav::kDegToRad;
using rnav::TrajectoryOptions;

namespace {
constexpr double kG = 9.80665;  // standard gravity, as documented for the turn radius

// Independent geometry of the default path (from TrajectoryOptions' documentation).
struct Geometry {
  double radius, turn, t_turn_start, t_turn_end, t_descent;
};
Geometry geometry(const TrajectoryOptions& o, const ApproachTrajectory& tr) {
  Geometry g;
  g.radius = o.speed_mps * o.speed_mps / (kG * std::tan(o.bank_deg * kDegToRad));
  const Eigen::Vector2d d1 =
      (Eigen::Vector2d(o.intercept_x_m, 0) - Eigen::Vector2d(o.start_x_m, o.start_z_m)).normalized();
  g.turn = std::acos(-d1.x());  // angle between d1 and final's direction (-1, 0)
  g.t_turn_end = tr.final_time_s();
  g.t_turn_start = g.t_turn_end - g.radius * g.turn / o.speed_mps;
  // final leg: x decreases at speed V from the turn's end point
  const double x_final0 = tr.at(g.t_turn_end).p_TA_L.x();
  const double descent_x = o.aim_x_m + o.start_y_m / std::tan(o.glide_deg * kDegToRad);
  g.t_descent = g.t_turn_end + (x_final0 - descent_x) / o.speed_mps;
  return g;
}
}  // namespace

TEST_CASE("trajectory starts at the paper's point and flies level towards the intercept",
          "[trajectory]") {
  const TrajectoryOptions o;
  const ApproachTrajectory tr(o);
  const auto k0 = tr.at(0.0);
  CHECK(k0.p_TA_L.x() == Approx(30860).margin(1e-9));
  CHECK(k0.p_TA_L.y() == Approx(400).margin(1e-9));
  CHECK(k0.p_TA_L.z() == Approx(9860).margin(1e-9));
  // first leg heads for (intercept_x, 0) in the (x, z) plane, level
  const Eigen::Vector2d d1 = Eigen::Vector2d(27000 - 30860, 0 - 9860).normalized();
  CHECK(k0.v_A_L.x() == Approx(75 * d1.x()).epsilon(1e-12));
  CHECK(k0.v_A_L.z() == Approx(75 * d1.y()).epsilon(1e-12));
  CHECK(k0.v_A_L.y() == 0.0);
  // turn radius r = V^2 / (g tan(bank)) and the descent start x = aim + start_y / tan(glide)
  CHECK(tr.turn_radius_m() == Approx(75.0 * 75.0 / (kG * std::tan(25 * kDegToRad))).epsilon(1e-12));
  CHECK(tr.descent_x_m() ==
        Approx(-300 + 400 / std::tan((2 + 40.0 / 60) * kDegToRad)).epsilon(1e-12));
}

TEST_CASE("horizontal speed is constant and the path is continuous", "[trajectory]") {
  const TrajectoryOptions o;
  const ApproachTrajectory tr(o);
  const double V = o.speed_mps, dt = 0.01, tan_g = std::tan(o.glide_deg * kDegToRad);
  auto prev = tr.at(0.0);
  long n = 0, bad_speed = 0, bad_jump_h = 0, bad_jump_v = 0;
  for (double t = dt; t <= tr.duration_s(); t += dt, ++n) {
    const auto k = tr.at(t);
    if (std::abs(std::hypot(k.v_A_L.x(), k.v_A_L.z()) - V) > 1e-9 * V) ++bad_speed;
    // horizontal arc length in dt is V dt; a chord is never longer
    const double dh = std::hypot(k.p_TA_L.x() - prev.p_TA_L.x(), k.p_TA_L.z() - prev.p_TA_L.z());
    if (dh > V * dt + 1e-9) ++bad_jump_h;
    // the climb/descent rate never exceeds V tan(glide)
    if (std::abs(k.p_TA_L.y() - prev.p_TA_L.y()) > V * tan_g * dt + 1e-9) ++bad_jump_v;
    prev = k;
  }
  CHECK(n > 30000);  // ~ 500 s sampled at 10 ms
  CHECK(bad_speed == 0);
  CHECK(bad_jump_h == 0);
  CHECK(bad_jump_v == 0);
}

TEST_CASE("velocity equals the finite-difference derivative of position", "[trajectory]") {
  const TrajectoryOptions o;
  const ApproachTrajectory tr(o);
  const Geometry g = geometry(o, tr);
  const double V = o.speed_mps, h = 0.01;
  // On a circle of radius r the central difference (p(t+h) - p(t-h)) / 2h has magnitude
  // V sin(th)/th, th = V h / r: error <= V th^2 / 6. Where the path changes from straight to
  // circular the acceleration jumps (|a| <= V^2 / r), and the central difference is the mean
  // velocity over [t-h, t+h]: error <= a h / 2. Rounding of ~3e4 m coordinates adds ~1e-10.
  const double th = V * h / g.radius;
  const double smooth_bound = 1.01 * V * th * th / 6 + 1e-8;
  const double kink_bound = 1.01 * (V * V / g.radius) * h / 2 + 1e-8;
  long checked = 0, bad = 0;
  for (double t = h; t <= tr.duration_s() - h; t += 0.05) {
    if (std::abs(t - g.t_descent) < 2 * h) continue;  // vertical speed jumps 0 -> -V tan(glide)
    const Eigen::Vector3d vfd = (tr.at(t + h).p_TA_L - tr.at(t - h).p_TA_L) / (2 * h);
    const bool near_kink = std::abs(t - g.t_turn_start) < 2 * h || std::abs(t - g.t_turn_end) < 2 * h;
    const double bound = near_kink ? kink_bound : smooth_bound;
    ++checked;
    if ((vfd - tr.at(t).v_A_L).norm() > bound) {
      ++bad;
      if (bad < 5) WARN("t=" << t << " fd " << vfd.transpose() << " v " << tr.at(t).v_A_L.transpose());
    }
  }
  CHECK(checked > 9000);
  CHECK(bad == 0);
  // The turn actually happens: heading rate on the arc equals V / r.
  const double tm = 0.5 * (g.t_turn_start + g.t_turn_end);
  const auto a = tr.at(tm - 1), b = tr.at(tm + 1);
  const double ha = std::atan2(a.v_A_L.z(), a.v_A_L.x()), hb = std::atan2(b.v_A_L.z(), b.v_A_L.x());
  CHECK(std::abs(std::remainder(hb - ha, 2 * M_PI)) == Approx(2 * V / g.radius).epsilon(1e-9));
}

TEST_CASE("final approach: on the centreline, descent at glide_deg, ends at end_x_m",
          "[trajectory]") {
  const TrajectoryOptions o;
  const ApproachTrajectory tr(o);
  const Geometry g = geometry(o, tr);
  const double tan_g = std::tan(o.glide_deg * kDegToRad);
  long n_desc = 0, n_level = 0;
  for (double t = g.t_turn_end + 0.5; t <= tr.duration_s(); t += 0.5) {
    const auto k = tr.at(t);
    CHECK(std::abs(k.p_TA_L.z()) < 1e-6);
    CHECK(k.v_A_L.x() == Approx(-o.speed_mps).epsilon(1e-12));
    if (t > g.t_descent + 1e-6) {
      ++n_desc;
      CHECK(std::atan(-k.v_A_L.y() / std::abs(k.v_A_L.x())) ==
            Approx(o.glide_deg * kDegToRad).epsilon(1e-12));
      CHECK(k.p_TA_L.y() == Approx((k.p_TA_L.x() - o.aim_x_m) * tan_g).margin(1e-6));
    } else if (t < g.t_descent - 1e-6) {
      ++n_level;
      CHECK(k.p_TA_L.y() == o.start_y_m);
      CHECK(k.v_A_L.y() == 0.0);
    }
  }
  CHECK(n_desc > 100);
  CHECK(n_level > 100);
  const auto kend = tr.at(tr.duration_s());
  CHECK(kend.p_TA_L.x() == Approx(o.end_x_m).margin(1e-6));
  CHECK(kend.p_TA_L.y() == Approx((o.end_x_m - o.aim_x_m) * tan_g).margin(1e-6));
  // clamped beyond the end and before the start
  CHECK((tr.at(tr.duration_s() + 100).p_TA_L - kend.p_TA_L).norm() < 1e-9);
  CHECK((tr.at(-5).p_TA_L - tr.at(0).p_TA_L).norm() < 1e-9);
}

TEST_CASE("impossible approach geometry throws ConfigError", "[trajectory]") {
  {
    TrajectoryOptions o;
    o.bank_deg = 1;  // r ~ 33 km: the turn cannot fit before the intercept point
    CHECK_THROWS_AS(ApproachTrajectory(o), rnav::ConfigError);
  }
  {
    TrajectoryOptions o;
    // Final starts near x = 8000 - r tan(turn/2) ~ 7750 m, but the level leg meets the glide
    // path at x ~ 8290 m: the descent would begin before the aircraft is on final.
    o.intercept_x_m = 8000;
    CHECK_THROWS_AS(ApproachTrajectory(o), rnav::ConfigError);
    CHECK_THROWS_WITH(ApproachTrajectory(o), Catch::Contains("descent"));
  }
  {
    TrajectoryOptions o;
    o.end_x_m = 26900;  // beyond the end of the turn (x ~ 26160 m)
    CHECK_THROWS_AS(ApproachTrajectory(o), rnav::ConfigError);
  }
  {
    TrajectoryOptions o;
    o.start_x_m = 27000;
    o.start_z_m = 0;  // start on the intercept point
    CHECK_THROWS_AS(ApproachTrajectory(o), rnav::ConfigError);
  }
  {
    TrajectoryOptions o;
    o.start_x_m = 20000;  // first leg points away from final (x increasing)
    o.start_z_m = 10;
    CHECK_THROWS_AS(ApproachTrajectory(o), rnav::ConfigError);
  }
  // and the default geometry is valid
  CHECK_NOTHROW(ApproachTrajectory(TrajectoryOptions{}));
}
