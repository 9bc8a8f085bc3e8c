// Unit tests of common/physics/frames.hpp: local-level frames on WGS84, NED velocities, rigid transforms
// between frames, radar polar coordinates and their Jacobian, angle wrapping.
#include "common/physics/bearing.hpp"
#include "common/physics/frames.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

using rnav::Geodetic;
using rnav::kDegToRad;
using rnav::LocalLevelFrame;
using rnav::bearing_jacobian;
using rnav::bearing_rad;
using rnav::bearing_rate_radps;
using rnav::range_jacobian;
using rnav::wrap_pi;

namespace {

// LOWW runway 29 threshold (the scenario default) and a high-latitude site.
const Geodetic kLoww{48.10153, 16.58495, 228.0};
const Geodetic kNorth{67.5, -20.25, 15.0};
const std::vector<double> kBearings{0.0, 90.0, 295.9, 115.9, -30.0, 359.0};

std::vector<Eigen::Vector3d> sample_points() {
  return {{30860, 400, 9860}, {-5000, 100, 2000}, {1000, -50, -3000}, {0, 0, 0}, {12.5, 3.0, -7.25}};
}

}  // namespace

TEST_CASE("from_geodetic and to_geodetic are inverse (sub-mm)", "[frames]") {
  for (const Geodetic& o : {kLoww, kNorth}) {
    for (double b : kBearings) {
      const LocalLevelFrame F(o, b);
      for (const auto& p : sample_points()) {
        const Geodetic g = F.to_geodetic(p);
        const Eigen::Vector3d back = F.from_geodetic(g);
        INFO("bearing " << b << " point " << p.transpose());
        // 0.1 mm over up to 32 km: both directions are closed-form ECEF rotations.
        CHECK((back - p).norm() < 1e-4);
        const Geodetic g2 = F.to_geodetic(F.from_geodetic(g));
        CHECK(std::abs(g2.lat_deg - g.lat_deg) < 1e-9);  // 1e-9 deg ~ 0.1 mm
        CHECK(std::abs(g2.lon_deg - g.lon_deg) < 1e-9);
        CHECK(std::abs(g2.h_m - g.h_m) < 1e-4);
      }
    }
  }
}

TEST_CASE("from_geodetic matches GeographicLib LocalCartesian rotated to the bearing", "[frames]") {
  const GeographicLib::LocalCartesian lc(kLoww.lat_deg, kLoww.lon_deg, kLoww.h_m);
  const LocalLevelFrame F0(kLoww, 0.0), F90(kLoww, 90.0), F180(kLoww, 180.0);
  const std::vector<Geodetic> pts{{48.2, 16.9, 600.0}, {48.0, 16.4, 100.0}, {48.1016, 16.5851, 230.0}};
  for (const auto& g : pts) {
    double e, n, u;
    lc.Forward(g.lat_deg, g.lon_deg, g.h_m, e, n, u);
    const Eigen::Vector3d p0 = F0.from_geodetic(g), p90 = F90.from_geodetic(g),
                          p180 = F180.from_geodetic(g);
    // bearing 0: x = north, y = up, z = east
    CHECK(p0.x() == Approx(n).margin(1e-6));
    CHECK(p0.y() == Approx(u).margin(1e-6));
    CHECK(p0.z() == Approx(e).margin(1e-6));
    // bearing 90: x = east, y = up, z = south
    CHECK(p90.x() == Approx(e).margin(1e-6));
    CHECK(p90.y() == Approx(u).margin(1e-6));
    CHECK(p90.z() == Approx(-n).margin(1e-6));
    // bearing 180: x = south, z = west
    CHECK(p180.x() == Approx(-n).margin(1e-6));
    CHECK(p180.z() == Approx(-e).margin(1e-6));
  }
}

TEST_CASE("x axis points along the bearing: a geodesic at azimuth b has course ~0", "[frames]") {
  const auto& geod = GeographicLib::Geodesic::WGS84();
  for (const Geodetic& o : {kLoww, kNorth}) {
    for (double b : kBearings) {
      double lat2, lon2;
      geod.Direct(o.lat_deg, o.lon_deg, b, 1000.0, lat2, lon2);
      const LocalLevelFrame F(o, b);
      const Eigen::Vector3d p = F.from_geodetic({lat2, lon2, o.h_m});
      const rnav::Polar q = rnav::polar_from_cartesian(p);
      INFO("origin lat " << o.lat_deg << " bearing " << b << " p " << p.transpose());
      // A geodesic leaves along its azimuth; its sideways departure from the tangent-plane
      // line is third order in d/R (~1e-9 rad at 1 km), so 1e-6 rad is a loose bound.
      CHECK(std::abs(q.course_rad) < 1e-6);
      // Along-track: the geodesic's 1 km is measured on the ellipsoid; at height h above it the
      // same angular separation spans 1000 (1 + h/R) m (R in [6.33e6, 6.42e6] m: the spread is
      // < 1e-3 m for h = 228 m); the tangent-plane projection shortens it by ~ 1e-6 m only.
      const double x_expected = 1000.0 * (1 + o.h_m / 6.375e6);
      CHECK(p.x() == Approx(x_expected).margin(2e-3));
      // The ellipsoid falls away below the tangent plane by d^2 / (2 R), R in [6.33e6, 6.42e6] m
      // (meridian / prime-vertical radii at these latitudes): 0.0779 .. 0.0790 m at 1 km.
      CHECK(-p.y() > 1e6 / (2 * 6.42e6) - 1e-4);
      CHECK(-p.y() < 1e6 / (2 * 6.33e6) + 1e-4);
    }
  }
}

TEST_CASE("from_ned and to_ned are inverse and north at the origin maps to (cos b, 0, -sin b)",
          "[frames]") {
  for (double b : kBearings) {
    const LocalLevelFrame F(kLoww, b);
    const double br = b * kDegToRad;
    const Eigen::Vector3d n = F.from_ned(kLoww, {1, 0, 0});
    const Eigen::Vector3d e = F.from_ned(kLoww, {0, 1, 0});
    const Eigen::Vector3d d = F.from_ned(kLoww, {0, 0, 1});
    INFO("bearing " << b);
    // x_F has ENU components (sin b, cos b, 0), z_F (cos b, -sin b, 0): north = (0, 1, 0) ENU.
    CHECK((n - Eigen::Vector3d(std::cos(br), 0, -std::sin(br))).norm() < 1e-12);
    CHECK((e - Eigen::Vector3d(std::sin(br), 0, std::cos(br))).norm() < 1e-12);
    CHECK((d - Eigen::Vector3d(0, -1, 0)).norm() < 1e-12);
    // inverse at arbitrary points and vectors
    for (const auto& p : sample_points()) {
      const Geodetic at = F.to_geodetic(p);
      const Eigen::Vector3d v(70.3, -12.1, 3.4);
      CHECK((F.to_ned(at, F.from_ned(at, v)) - v).norm() < 1e-12 * v.norm());
      CHECK((F.from_ned(at, F.to_ned(at, v)) - v).norm() < 1e-12 * v.norm());
    }
  }
}

TEST_CASE("from_ned agrees with the finite-difference motion of a point away from the origin",
          "[frames]") {
  // Move a point 30 km from the origin by a small NED displacement (via a LocalCartesian at the
  // point itself) and compare the change of its F coordinates with from_ned.
  const LocalLevelFrame F(kLoww, 115.9);
  const Geodetic P = F.to_geodetic({30860, 400, 9860});
  const GeographicLib::LocalCartesian lcP(P.lat_deg, P.lon_deg, P.h_m);
  const Eigen::Vector3d v_N(-40.0, 60.0, 3.5);  // [m/s]
  const double dt = 0.1;                        // 7 m displacement
  Geodetic P2;
  lcP.Reverse(v_N.y() * dt, v_N.x() * dt, -v_N.z() * dt, P2.lat_deg, P2.lon_deg, P2.h_m);
  const Eigen::Vector3d v_fd = (F.from_geodetic(P2) - F.from_geodetic(P)) / dt;
  const Eigen::Vector3d v_F = F.from_ned(P, v_N);
  // Both maps are rigid up to LocalCartesian's exactness; residual is rounding of ~3e4 m
  // coordinates (~1e-11 m) divided by dt.
  CHECK((v_fd - v_F).norm() < 1e-6 * v_N.norm());
  CHECK(v_F.norm() == Approx(v_N.norm()).epsilon(1e-12));
}

TEST_CASE("transform(to, from) equals going through geodetic coordinates", "[frames]") {
  const LocalLevelFrame L(kLoww, 115.9);
  const Geodetic radar = L.to_geodetic({-900, 0, 180});
  const std::vector<LocalLevelFrame> tos{LocalLevelFrame(radar, 115.9), LocalLevelFrame(radar, 40.0),
                                         LocalLevelFrame({48.3, 16.1, 500}, 270.0)};
  for (const auto& R : tos) {
    const Eigen::Isometry3d T = rnav::transform(R, L);
    CHECK((T.linear() * T.linear().transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK(T.linear().determinant() == Approx(1.0).epsilon(1e-12));
    for (const auto& p : sample_points()) {
      const Eigen::Vector3d via_geo = R.from_geodetic(L.to_geodetic(p));
      INFO("point " << p.transpose());
      CHECK(((T * p) - via_geo).norm() < 1e-3);  // mm
    }
    // and the inverse direction
    const Eigen::Isometry3d Tinv = rnav::transform(L, R);
    CHECK(((Tinv * T).matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-9);
  }
}

TEST_CASE("polar_from_cartesian and cartesian_from_polar are inverse", "[frames]") {
  for (const auto& p : std::vector<Eigen::Vector3d>{
           {30000, 400, 9860}, {-2000, 50, -3000}, {100, -20, 0.5}, {-5, 1, -1e-3}, {0.1, 1000, 0.2}}) {
    const rnav::Polar q = rnav::polar_from_cartesian(p);
    CHECK((rnav::cartesian_from_polar(q) - p).norm() < 1e-12 * p.norm());
    CHECK(q.range_m == Approx(p.norm()).epsilon(1e-15));
    CHECK(q.course_rad > -M_PI);
    CHECK(q.course_rad <= M_PI);
    CHECK(std::abs(q.glide_rad) <= M_PI / 2);
  }
  for (double D : {10.0, 25000.0})
    for (double ek : {-3.0, -1.0, 0.0, 0.7, 3.1})
      for (double eg : {-1.2, -0.01, 0.05, 1.5}) {
        const rnav::Polar q2 = rnav::polar_from_cartesian(rnav::cartesian_from_polar({D, ek, eg}));
        CHECK(q2.range_m == Approx(D).epsilon(1e-14));
        CHECK(q2.course_rad == Approx(ek).margin(1e-13));
        CHECK(q2.glide_rad == Approx(eg).margin(1e-13));
      }
}

TEST_CASE("polar_jacobian matches central finite differences", "[frames]") {
  for (const auto& p : std::vector<Eigen::Vector3d>{
           {30000, 400, 9860}, {-2000, 50, -3000}, {4000, 300, -150}, {100, -20, 7}}) {
    const Eigen::Matrix3d J = rnav::polar_jacobian(p);
    const double h = 1e-6 * p.norm();
    Eigen::Matrix3d Jfd;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[c] = h;
      const rnav::Polar a = rnav::polar_from_cartesian(p + dp), b = rnav::polar_from_cartesian(p - dp);
      Jfd(0, c) = (a.range_m - b.range_m) / (2 * h);
      Jfd(1, c) = (a.course_rad - b.course_rad) / (2 * h);
      Jfd(2, c) = (a.glide_rad - b.glide_rad) / (2 * h);
    }
    // Central differences: truncation ~ (h/|p|)^2 = 1e-12 relative, rounding ~ eps/1e-6 = 2e-10
    // relative to the row's scale; 1e-6 of the row norm is a comfortable bound (entries can be 0).
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        INFO("p " << p.transpose() << " entry " << r << "," << c);
        CHECK(std::abs(Jfd(r, c) - J(r, c)) <= 1e-6 * J.row(r).norm());
      }
  }
}

TEST_CASE("wrap_pi maps into the half-open interval from -pi to pi and keeps the angle modulo 2 pi", "[frames]") {
  CHECK(rnav::wrap_pi(M_PI) == M_PI);
  CHECK(rnav::wrap_pi(-M_PI) == M_PI);  // -pi is excluded
  CHECK(rnav::wrap_pi(0.0) == 0.0);
  CHECK(rnav::wrap_pi(0.5 + 2 * M_PI) == Approx(0.5).margin(1e-15));
  CHECK(rnav::wrap_pi(-0.5 - 4 * M_PI) == Approx(-0.5).margin(1e-14));
  const double just_below = std::nextafter(M_PI, 0.0);
  CHECK(rnav::wrap_pi(just_below) == just_below);
  const double just_above_minus = std::nextafter(-M_PI, 0.0);
  CHECK(rnav::wrap_pi(just_above_minus) == just_above_minus);
  // slightly beyond +pi wraps to slightly above -pi, slightly below -pi to slightly below +pi
  CHECK(rnav::wrap_pi(M_PI + 1e-9) == Approx(-M_PI + 1e-9).margin(1e-15));
  CHECK(rnav::wrap_pi(-M_PI - 1e-9) == Approx(M_PI - 1e-9).margin(1e-15));
  const double below_minus = std::nextafter(-M_PI, -4.0);
  CHECK(rnav::wrap_pi(below_minus) <= M_PI);
  CHECK(rnav::wrap_pi(below_minus) > 0);
  for (int k = -7; k <= 7; ++k) {
    for (double a : {M_PI, -M_PI, 3.0, -3.0, 0.1}) {
      const double x = a + 2 * M_PI * k, w = rnav::wrap_pi(x);
      INFO("x = " << x);
      CHECK(w > -M_PI);
      CHECK(w <= M_PI);
      const double turns = (x - w) / (2 * M_PI);
      CHECK(std::abs(turns - std::round(turns)) < 1e-12);
    }
  }
}

TEST_CASE("bearing: clockwise from north, its Jacobians and rate against finite differences") {
  // hand values: north 0, east 90 deg, south 180 deg, north-west -45 deg
  CHECK(bearing_rad(Eigen::Vector2d(1, 0)) == 0);
  CHECK(bearing_rad(Eigen::Vector2d(0, 2)) == Approx(M_PI / 2));
  CHECK(bearing_rad(Eigen::Vector2d(-3, 0)) == Approx(M_PI));
  CHECK(bearing_rad(Eigen::Vector2d(5, -5)) == Approx(-M_PI / 4));
  // central differences with step h = 1e-4 |d|: truncation O(h^2 / |d|^3) ~ 1e-8 of |J|, rounding
  // ~ 1e-16 / h; tolerance 1e-7 relative to the gradient's size
  for (const Eigen::Vector2d& d : {Eigen::Vector2d(300, 40), Eigen::Vector2d(-20, 7), Eigen::Vector2d(-5e3, -2e3)}) {
    const double h = 1e-4 * d.norm();
    Eigen::RowVector2d jb, jr;
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2d e = Eigen::Vector2d::Zero();
      e(i) = h;
      jb(i) = wrap_pi(bearing_rad(d + e) - bearing_rad(d - e)) / (2 * h);
      jr(i) = ((d + e).norm() - (d - e).norm()) / (2 * h);
    }
    CHECK((bearing_jacobian(d) - jb).norm() < 1e-7 * jb.norm());
    CHECK((range_jacobian(d) - jr).norm() < 1e-7);
    const Eigen::Vector2d v(3, -8);  // [m/s]
    const double dt = 1e-3;          // [s]
    const double rate = wrap_pi(bearing_rad(d + v * dt) - bearing_rad(d - v * dt)) / (2 * dt);
    CHECK(bearing_rate_radps(d, v) == Approx(rate).epsilon(1e-6));
    CHECK(bearing_rate_radps(d, v) == Approx(bearing_jacobian(d) * v).epsilon(1e-12));
  }
}
