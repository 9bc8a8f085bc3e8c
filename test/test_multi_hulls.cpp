// The multi-sensor diagnosis on a radar picture of long hulls (a generator of its own, not the
// project's simulator nor flightgen): a radar at rest, six ships with AIS-like references at
// their hull centres, each range the distance to the nearest point of its hull rectangle (the
// near side), each bearing the centre's. A ship that passes the radar shows its hull end-on,
// then broadside, then end-on: its near-side echo depends on its aspect and is named as such
// (near_side_echo, half-length and half-beam); a moored ship seen from one place shows one
// aspect, and its echo is one constant (echo_range_offset).
#include "common/io/config.hpp"
#include "common/physics/frames.hpp"
#include "estimators/diagnosis/multi_diagnose.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace rnav;

namespace {

struct Ship {
  Eigen::Vector2d p0;      // [m] hull centre at t = 0, (east, north) from the radar
  double course_rad = 0;   // clockwise from north
  double speed_mps = 0;    // 0: moored
  double length_m = 0, beam_m = 0;
};

// Six ships: 1 long (200 m x 30 m) passing 900 m off at 6 m/s, 2-5 short ones passing
// elsewhere, 6 moored (150 m x 20 m) 1500 m off, its end 30 deg off the line of sight.
std::vector<Ship> ships() {
  const double d = kDegToRad;
  return {{{-2700, 900}, 90 * d, 6, 200, 30},  {{2500, -1200}, 270 * d, 5, 30, 6},   {{-900, -2600}, 0 * d, 5, 25, 5},
          {{1800, 2500}, 200 * d, 7, 20, 5},   {{-2200, -2000}, 60 * d, 4, 35, 7},   {{750, 1300}, 60 * d, 0, 150, 20}};
}

Eigen::Vector2d along(double course_rad) { return {std::sin(course_rad), std::cos(course_rad)}; }

Eigen::Vector2d centre(const Ship& s, double t) { return s.p0 + s.speed_mps * t * along(s.course_rad); }

// The distance from the radar (origin) to the nearest point of ship s's hull rectangle at t.
double near_side_range(const Ship& s, double t) {
  const Eigen::Vector2d c = centre(s, t), u = along(s.course_rad), v(u.y(), -u.x());  // v: starboard
  // the origin in hull coordinates, clamped into the rectangle: its nearest point
  const double x = std::clamp(-c.dot(u), -s.length_m / 2, s.length_m / 2), y = std::clamp(-c.dot(v), -s.beam_m / 2, s.beam_m / 2);
  return (c + x * u + y * v).norm();
}

constexpr double kScanS = 2.5, kDurationS = 900, kSigmaRangeM = 10, kSigmaBearingDeg = 0.3;

MultiSensorData make(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  const LocalLevelFrame F({59.9, 10.7, 20.0}, 0.0);
  auto geo = [&](const Eigen::Vector2d& en) { return F.to_geodetic(Eigen::Vector3d(en.y(), 0, en.x())); };  // (north, 0, east)
  MultiSensorData d;
  for (double t = 0; t <= kDurationS; t += 1) d.observer.push_back({t, geo({0, 0})});
  d.observer_heading_deg.assign(d.observer.size(), NAN);
  const auto S = ships();
  for (std::size_t k = 0; k < S.size(); ++k) {
    auto& tr = d.truth[std::to_string(k + 1)];
    for (double t = 0; t <= kDurationS; t += 2) tr.push_back({t, geo(centre(S[k], t))});
  }
  for (double t = kScanS; t < kDurationS - kScanS; t += kScanS)
    for (std::size_t k = 0; k < S.size(); ++k) {
      const Eigen::Vector2d c = centre(S[k], t);
      const double b = std::atan2(c.x(), c.y()) + kSigmaBearingDeg * kDegToRad * N(rng);
      d.detections.push_back({t, "radar", near_side_range(S[k], t) + kSigmaRangeM * N(rng), wrap_pi(b), NAN});
    }
  return d;
}

MultiDiagnoseOptions options() {
  MultiDiagnoseOptions o;
  o.sigma_bearing_deg = kSigmaBearingDeg;
  o.sigma_range_m = kSigmaRangeM;
  o.association.gate_position_m = 200;  // a 200 m hull's echo is up to 100 m short of its centre
  o.association.gate_bearing_deg = 4;
  o.test_target_model = false;
  return o;
}

const FoundEffect* find(const MultiReport& r, const std::string& name, const std::string& target) {
  for (const auto& e : r.result.effects)
    if (e.name == name && e.scope.target == target) return &e;
  return nullptr;
}

}  // namespace

TEST_CASE("multi diagnosis: a passing ship's echo by its aspect, a moored ship's as one constant") {
  const MultiReport r = diagnose_multi(make(3), options());
  INFO(r.text());
  // ship 1: a = L/2 = 100 m, b = B/2 = 15 m; the near-side model is the far field's, and the
  // nearest corner's sideways distance p adds p^2 / 2r (p <= 100 m at r >= 900 m: <= 5.6 m)
  const FoundEffect* e = find(r, "near_side_echo", "1");
  REQUIRE(e);
  CHECK(e->scope.sensor == "radar");
  const double far_field_m = 100.0 * 100.0 / (2 * 900);
  CHECK(std::abs(e->estimate[0] - 100) < 3 * e->stderr_[0] + far_field_m);
  CHECK(std::abs(e->estimate[1] - 15) < 3 * e->stderr_[1] + far_field_m);
  CHECK_FALSE(find(r, "echo_range_offset", "1"));
  // ship 6, moored, seen from one place: one aspect, one constant, short by about its half-length
  // projected on the line of sight, 75 cos 30 deg + 10 sin 30 deg = 70 m
  const FoundEffect* m = find(r, "echo_range_offset", "6");
  REQUIRE(m);
  CHECK(std::abs(m->estimate[0] + 70) < 3 * m->stderr_[0] + 75.0 * 75.0 / (2 * 1500));
  CHECK_FALSE(find(r, "near_side_echo", "6"));
  // no radar-wide range error stands in for the hulls
  for (const auto& x : r.result.effects) {
    CHECK(x.name != "range_bias");
    CHECK(x.name != "range_gain");
  }
}

TEST_CASE("multi diagnosis: a near-side echo beyond the hull on record is refused") {
  // ship 1 on record as 40 m x 8 m: a half-length of 100 m cannot lie on it
  MultiSensorData d = make(3);
  d.hull["1"] = {40.0, 8.0};
  const MultiReport r = diagnose_multi(d, options());
  INFO(r.text());
  CHECK_FALSE(find(r, "near_side_echo", "1"));
  bool refused = false;
  for (const auto& x : r.result.refused)
    if (x.name == "near_side_echo" && x.scope.target == "1") {
      refused = true;
      CHECK(x.reason.find("beyond the hull of target 1") != std::string::npos);
    }
  CHECK(refused);
}
