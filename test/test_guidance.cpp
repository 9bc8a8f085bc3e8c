// The UAV's closed-loop guidance (sim/uav/guidance.hpp): the turn's direction, its limits, the
// wind correction, the exact kinematics, and the loop closed on a stationary object.
#include "sim/uav/guidance.hpp"

#include "common/physics/frames.hpp"
#include "sim/uav/observer_options.hpp"

#include <catch2/catch.hpp>

#include <cmath>

namespace g = rnav::guidance;
using rnav::kDegToRad;

namespace {

g::Limits limits(const std::string& direction = "ccw", double wind_n = 0, double wind_e = 0) {
  rnav::ObserverOptions o;
  o.direction = direction;
  o.wind_north_mps = wind_n;
  o.wind_east_mps = wind_e;
  return g::Limits::from(o);
}

}  // namespace

TEST_CASE("guidance: the course keeps the object on the orbit's side, turning towards it when far", "[guidance]") {
  // Object due east (bearing 90 deg), at the standoff range: ccw puts it on the left (course
  // north-east + 90 = 180 deg, south), cw on the right (course 0, north).
  CHECK(g::desired_course(limits("ccw"), 90 * kDegToRad, 300.0) == Approx(M_PI).margin(1e-12));
  CHECK(std::abs(rnav::wrap_pi(g::desired_course(limits("ccw"), 90 * kDegToRad, 300.0) - M_PI)) < 1e-12);
  CHECK(g::desired_course(limits("cw"), 90 * kDegToRad, 300.0) == Approx(0.0).margin(1e-12));
  // Farther than the standoff: the course turns towards the bearing (90 deg), by atan(k (r-R)/R).
  const double far = g::desired_course(limits("ccw"), 90 * kDegToRad, 600.0);
  CHECK(far == Approx(M_PI - M_PI / 4));  // atan(1 * 300/300) = 45 deg
  const double far_cw = g::desired_course(limits("cw"), 90 * kDegToRad, 600.0);
  CHECK(far_cw == Approx(M_PI / 4));
  // Closer: away from the object.
  CHECK(rnav::wrap_pi(g::desired_course(limits("ccw"), 90 * kDegToRad, 150.0) - M_PI) > 0.0);
  // Range unknown: perpendicular.
  CHECK(g::desired_course(limits("cw"), 90 * kDegToRad, std::nullopt) == Approx(0.0).margin(1e-12));
}

TEST_CASE("guidance: turn-rate command has the orbit's sign and stays within the bank and rate limits", "[guidance]") {
  const g::Limits ccw = limits("ccw"), cw = limits("cw");
  // omega_max = min(20 deg/s, g tan(30 deg) / 20 m/s) = 0.2831 rad/s (16.2 deg/s): the bank limit.
  CHECK(ccw.max_turn_rate_radps == Approx(g::kGravity * std::tan(30 * kDegToRad) / 20.0));
  CHECK(ccw.max_turn_rate_radps < 20 * kDegToRad);
  // On course: only the orbit's feed-forward, s V / R (ccw: course decreasing).
  CHECK(g::turn_rate_command(ccw, 0.3, 0.3) == Approx(-20.0 / 300.0));
  CHECK(g::turn_rate_command(cw, 0.3, 0.3) == Approx(20.0 / 300.0));
  // A desired heading to the right (clockwise) turns right; far off, the command saturates.
  CHECK(g::turn_rate_command(cw, 0.0, 0.2) > 0);
  CHECK(g::turn_rate_command(ccw, 0.0, 0.5) > 0);
  CHECK(g::turn_rate_command(ccw, 0.0, 3.0) == Approx(ccw.max_turn_rate_radps));
  CHECK(g::turn_rate_command(cw, 0.0, -3.0) == Approx(-cw.max_turn_rate_radps));
  // The error wraps: desired 179 deg from heading -179 deg is 2 deg to the left, not 358 to the right.
  CHECK(g::turn_rate_command(cw, -179 * kDegToRad, 179 * kDegToRad) < 20.0 / 300.0);
  // A low turn-rate limit takes over from the bank limit.
  rnav::ObserverOptions o;
  o.max_turn_rate_dps = 2;
  CHECK(g::Limits::from(o).max_turn_rate_radps == Approx(2 * kDegToRad));
}

TEST_CASE("guidance: the heading makes good the desired course in the wind", "[guidance]") {
  const g::Limits l = limits("ccw", 3.0, -6.0);  // 6.7 m/s of wind at 20 m/s airspeed
  for (double chi_deg : {0.0, 37.0, 90.0, 181.0, -120.0}) {
    const double chi = chi_deg * kDegToRad;
    const Eigen::Vector2d v = g::ground_velocity(l, g::heading_for_course(l, chi));
    // The ground velocity points along chi: its component across the course is zero.
    CHECK(std::cos(chi) * v.y() - std::sin(chi) * v.x() == Approx(0.0).margin(1e-12));
    CHECK(std::cos(chi) * v.x() + std::sin(chi) * v.y() > 0);
  }
}

TEST_CASE("guidance: the constant-turn step is exact (small Euler steps converge to it)", "[guidance]") {
  const g::Limits l = limits("cw", 2.0, 1.0);
  g::UavState x;
  x.p_OU_F = Eigen::Vector2d(100, -50);
  x.heading_rad = 0.4;
  for (double omega : {0.0, 0.05, -0.2831}) {
    const g::UavState exact = g::propagate(l, x, omega, 2.0);
    g::UavState e = x;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {  // midpoint steps, error O(dt^2) ~ 1e-8 m
      const double dt = 2.0 / n, psi_mid = e.heading_rad + 0.5 * omega * dt;
      e.p_OU_F += g::ground_velocity(l, psi_mid) * dt;
      e.heading_rad += omega * dt;
    }
    CHECK((exact.p_OU_F - e.p_OU_F).norm() < 1e-6);
    CHECK(rnav::wrap_pi(exact.heading_rad - e.heading_rad) == Approx(0.0).margin(1e-9));
  }
}

TEST_CASE("guidance: closed on a stationary object with known range, the UAV settles on the orbit", "[guidance]") {
  // The UAV starts 1 km out, heading away; with the true bearing and range at 5 Hz it must turn
  // (within the limits), close in and circle the object at the standoff range, object on its left.
  for (const char* dir : {"ccw", "cw"}) {
    INFO(dir);
    const g::Limits l = limits(dir);
    g::UavState x;
    x.p_OU_F = Eigen::Vector2d(-1000, 0);
    x.heading_rad = M_PI;  // south, away from the object at the origin
    double r_min = 1e9, r_max = 0, max_rate = 0, turned = 0;
    for (int k = 0; k < 5 * 300; ++k) {
      const Eigen::Vector2d d = -x.p_OU_F;
      const double beta = std::atan2(d.y(), d.x()), r = d.norm();
      const double omega = g::turn_rate_command(l, x.heading_rad, g::heading_for_course(l, g::desired_course(l, beta, r)));
      max_rate = std::max(max_rate, std::abs(omega));
      x = g::propagate(l, x, omega, 0.2);
      if (k >= 5 * 150) {  // the second half: on the orbit
        r_min = std::min(r_min, r);
        r_max = std::max(r_max, r);
        turned += omega * 0.2;
      }
    }
    CHECK(max_rate <= l.max_turn_rate_radps + 1e-15);
    CHECK(r_min > 290);  // within 10 m of the 300 m standoff
    CHECK(r_max < 310);
    // 150 s at 20 m/s on a 300 m circle: 10 rad, turning the orbit's way (ccw negative).
    CHECK(turned * l.orbit_sense == Approx(150 * 20.0 / 300.0).epsilon(0.05));
  }
}
