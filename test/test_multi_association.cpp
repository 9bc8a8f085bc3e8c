// Association with gates recentred on each sensor's common bias, on data from a generator of its
// own: an observer moving slowly near 63.44 N 10.40 E, two targets on straight lines 330-500 m
// away (more than 60 deg apart in bearing all the time), a radar (range and bearing every 1.7 s)
// and a camera "eo" (bearing every 0.2 s), white noise, missed detections and clutter in every
// scan. A sensor bias beyond its gate (radar 5 deg: 29 m or more at 330 m, beyond the 20 m
// position gate; eo 6 deg, beyond the 3 deg gate) must not cost the association its detections,
// the shifts must be the biases within their standard errors, nominal data must associate
// exactly as without recentring, and the associated measurements must stay the raw ones.
#include "estimators/diagnosis/multi_association.hpp"
#include "estimators/diagnosis/multi_diagnose.hpp"
#include "estimators/diagnosis/plane_series.hpp"
#include "estimators/diagnosis/reference_jumps.hpp"
#include "estimators/diagnosis/io/autoferry_import.hpp"

#include "common/io/config.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <random>
#include <tuple>

using namespace rnav;

namespace {

constexpr double kSpanS = 200;                                     // [s] observer and references from t = 0
constexpr double kObserverDtS = 0.1;                               // [s] observer sample interval
constexpr double kTruthDtS = 0.2;                                  // [s] reference sample interval
constexpr double kFirstScanS = 5, kLastScanS = 195;                // [s] scans inside the references' span
constexpr double kRadarDtS = 1.7, kEoDtS = 0.2;                    // [s] scan intervals
constexpr double kRadarSigmaBearingDeg = 0.3;                      // [deg] white bearing noise
constexpr double kRadarSigmaRangeM = 2.0;                          // [m] white range noise
constexpr double kEoSigmaBearingDeg = 0.2;                         // [deg] white bearing noise
constexpr double kMissProbability = 0.1;                           // a target's detection missing from a scan
constexpr int kRadarClutter = 3, kEoClutter = 2;                   // clutter detections per scan
constexpr double kClutterMinRangeM = 50, kClutterMaxRangeM = 700;  // [m] radar clutter ranges, uniform
// Robust standard error of a median of n Gaussian residuals of sigma: sqrt(pi/2) sigma / sqrt(n).
constexpr double kMedianSeFactor = 1.2533141373155003;
// Tolerance of an estimated shift: 4 standard errors of its median over the sensor's wide-pass
// pairs (n = SensorAssociation::wide_pairs; 160-180 radar pairs: 0.11 deg and 0.75 m, 1370 eo
// pairs: 0.027 deg). The clutter left in the unambiguous pairs (a missed target with one clutter
// detection inside its wide gate: about 3 % of them, spread over the whole wide gate) moves a
// median by at most a third of an SE here.
constexpr double kToleranceSe = 4;

struct Bias {
  double radar_bearing_rad = 0;  // added to every radar bearing of a target
  double radar_range_m = 0;      // added to every radar range of a target
  double eo_bearing_rad = 0;     // added to every eo bearing of a target
};

// A target's detection as generated (measured values, biases and noise included).
struct TrueDetection {
  double bearing_rad, range_m;
};
using Key = std::tuple<std::string, double, std::string>;  // sensor, t_s, target

struct Scene {
  MultiSensorData data;
  std::map<Key, TrueDetection> targets;  // every target detection generated
};

// (north, east) [m] in the frame at the fixed point
Eigen::Vector2d own(double t) { return {0.3 * t, 10 * std::sin(t / 50)}; }
Eigen::Vector2d target_pos(int k, double t) {
  return k == 1 ? Eigen::Vector2d(350, -200 + 3 * t) : Eigen::Vector2d(-400 + 1 * t, -100 + 2.5 * t);
}

// A jump of target 1's reference (its GNSS fix changing): the reference moves by east_m from t_s
// on; the target and its detections do not.
struct RefJump {
  double t_s = -1;    // [s] none before 0
  double east_m = 0;  // [m]
};

Scene make(std::uint64_t seed, const Bias& bias, const RefJump& jump = {}) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  std::uniform_real_distribution<double> U(0, 1);
  const LocalLevelFrame F({63.44, 10.40, 40.0}, 0.0);
  auto geo = [&](const Eigen::Vector2d& p) { return F.to_geodetic(Eigen::Vector3d(p.x(), 0, p.y())); };
  Scene sc;
  MultiSensorData& d = sc.data;
  for (int n = 0; n * kObserverDtS <= kSpanS + 1e-9; ++n)
    d.observer.push_back({n * kObserverDtS, geo(own(n * kObserverDtS))});
  d.observer_heading_deg.assign(d.observer.size(), NAN);
  for (int k = 1; k <= 2; ++k)
    for (int n = 0; n * kTruthDtS <= kSpanS + 1e-9; ++n)
      d.truth[std::to_string(k)].push_back(
          {n * kTruthDtS, geo(target_pos(k, n * kTruthDtS) +
                              Eigen::Vector2d(0, k == 1 && jump.t_s >= 0 && n * kTruthDtS >= jump.t_s ? jump.east_m : 0.0))});
  struct Sensor {
    std::string name;
    double dt_s, sigma_bearing_rad, sigma_range_m, bias_bearing_rad, bias_range_m;
    int clutter;
    bool ranged;
  };
  const Sensor sensors[] = {
      {"radar", kRadarDtS, kRadarSigmaBearingDeg * kDegToRad, kRadarSigmaRangeM, bias.radar_bearing_rad,
       bias.radar_range_m, kRadarClutter, true},
      {"eo", kEoDtS, kEoSigmaBearingDeg * kDegToRad, 0, bias.eo_bearing_rad, 0, kEoClutter, false}};
  for (const auto& s : sensors)
    for (int n = 0; kFirstScanS + n * s.dt_s <= kLastScanS; ++n) {
      const double t = kFirstScanS + n * s.dt_s;
      for (int k = 1; k <= 2; ++k) {
        const bool missed = U(rng) < kMissProbability;
        const Eigen::Vector2d rel = target_pos(k, t) - own(t);
        const double b = wrap_pi(std::atan2(rel.y(), rel.x()) + s.bias_bearing_rad + s.sigma_bearing_rad * N(rng));
        const double r = s.ranged ? rel.norm() + s.bias_range_m + s.sigma_range_m * N(rng) : NAN;
        if (missed) continue;
        d.detections.push_back({t, s.name, r, b, NAN});
        sc.targets[Key{s.name, t, std::to_string(k)}] = {b, r};
      }
      for (int c = 0; c < s.clutter; ++c) {
        const double r = kClutterMinRangeM + (kClutterMaxRangeM - kClutterMinRangeM) * U(rng);
        d.detections.push_back({t, s.name, s.ranged ? r : NAN, wrap_pi(2 * M_PI * U(rng)), NAN});
      }
    }
  return sc;
}

// Share of the sensor's generated target detections associated to their own target.
double found_share(const Scene& sc, const std::vector<AssociatedDetection>& a, const std::string& sensor) {
  int generated = 0, found = 0;
  for (const auto& [key, x] : sc.targets) generated += std::get<0>(key) == sensor;
  for (const auto& x : a) {
    const auto it = sc.targets.find(Key{x.sensor, x.t_s, x.target});
    found += x.sensor == sensor && it != sc.targets.end() && it->second.bearing_rad == x.bearing_rad;
  }
  return generated ? static_cast<double>(found) / generated : 0.0;
}

AssociationOptions off() {
  AssociationOptions o;
  o.recentre_gates = false;
  return o;
}

// Same detections, same geometry, same tallies.
void check_same(const std::vector<AssociatedDetection>& a, const std::vector<AssociatedDetection>& b,
                const std::map<std::string, SensorAssociation>& sa,
                const std::map<std::string, SensorAssociation>& sb) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO(i);
    CHECK(a[i].t_s == b[i].t_s);
    CHECK(a[i].sensor == b[i].sensor);
    CHECK(a[i].target == b[i].target);
    CHECK(a[i].bearing_rad == b[i].bearing_rad);
    CHECK(a[i].range_m == b[i].range_m);
    CHECK(a[i].d == b[i].d);
    CHECK(a[i].v_rel == b[i].v_rel);
  }
  REQUIRE(sa.size() == sb.size());
  for (const auto& [s, x] : sa) {
    INFO(s);
    const SensorAssociation& y = sb.at(s);
    CHECK(x.scans == y.scans);
    CHECK(x.detections == y.detections);
    CHECK(x.ambiguous_scans == y.ambiguous_scans);
    CHECK(x.associated == y.associated);
    CHECK(x.missed == y.missed);
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Autoferry scenario 4 as imported (the test fails where the recording is missing).
MultiSensorData autoferry_scenario4() {
  const std::string data = std::string(RNAV_DATA_DIR) + "/autoferry/scenario4";
  if (!std::filesystem::exists(data)) FAIL("the Autoferry recording is not at " << data);
  return autoferry_to_multi(load_autoferry(data));
}

}  // namespace

TEST_CASE("multi association: bearing biases beyond the gates are associated once the gates are recentred") {
  Bias b;
  b.radar_bearing_rad = 5 * kDegToRad;  // 29-44 m across the line of sight at 330-500 m: 20 m gate
  b.eo_bearing_rad = 6 * kDegToRad;     // 3 deg gate
  const Scene sc = make(11, b);
  std::map<std::string, SensorAssociation> st_on, st_off;
  const auto on = associate(sc.data, AssociationOptions{}, st_on);
  const auto no = associate(sc.data, off(), st_off);
  for (const char* s : {"radar", "eo"}) {
    INFO(s << ": " << found_share(sc, on, s) << " recentred, " << found_share(sc, no, s) << " not; shifts "
           << st_on.at(s).gate_shift_bearing_rad << " rad " << st_on.at(s).gate_shift_range_m << " m from "
           << st_on.at(s).wide_pairs << " pairs");
    CHECK(found_share(sc, on, s) >= 0.85);
    CHECK(found_share(sc, no, s) < 0.20);
    CHECK(st_off.at(s).wide_pairs == 0);  // off: no first pass
    CHECK(st_off.at(s).gate_shift_bearing_rad == 0);
  }
}

TEST_CASE("multi association: the gate shifts are the sensors' biases within 4 standard errors") {
  Bias b;
  b.radar_bearing_rad = 5 * kDegToRad;
  b.radar_range_m = 40;  // beyond the 20 m gate on its own
  b.eo_bearing_rad = -6 * kDegToRad;
  const Scene sc = make(12, b);
  std::map<std::string, SensorAssociation> st;
  const auto a = associate(sc.data, AssociationOptions{}, st);
  const SensorAssociation &radar = st.at("radar"), &eo = st.at("eo");
  INFO("radar: " << radar.gate_shift_bearing_rad / kDegToRad << " deg, " << radar.gate_shift_range_m << " m from "
                 << radar.wide_pairs << " pairs; eo " << eo.gate_shift_bearing_rad / kDegToRad << " deg from "
                 << eo.wide_pairs);
  REQUIRE(radar.wide_pairs >= 10);
  REQUIRE(eo.wide_pairs >= 10);
  // tolerance: kToleranceSe standard errors of a median of the generator's white noise over the pairs
  const auto tol = [](double sigma, int n) { return kToleranceSe * kMedianSeFactor * sigma / std::sqrt(double(n)); };
  CHECK(std::abs(radar.gate_shift_bearing_rad - b.radar_bearing_rad) <
        tol(kRadarSigmaBearingDeg * kDegToRad, radar.wide_pairs));
  CHECK(std::abs(radar.gate_shift_range_m - b.radar_range_m) < tol(kRadarSigmaRangeM, radar.wide_pairs));
  CHECK(std::abs(eo.gate_shift_bearing_rad - b.eo_bearing_rad) < tol(kEoSigmaBearingDeg * kDegToRad, eo.wide_pairs));
  CHECK(eo.gate_shift_range_m == 0);  // bearing-only
  CHECK(found_share(sc, a, "radar") >= 0.85);
  CHECK(found_share(sc, a, "eo") >= 0.85);
}

TEST_CASE("multi association: nominal data apply no shift and associate exactly as without recentring") {
  const Scene sc = make(13, Bias{});
  std::map<std::string, SensorAssociation> st_on, st_off;
  const auto on = associate(sc.data, AssociationOptions{}, st_on);
  const auto no = associate(sc.data, off(), st_off);
  for (const char* s : {"radar", "eo"}) {
    INFO(s);
    CHECK(st_on.at(s).wide_pairs >= 10);  // estimated, and found not significant
    CHECK(st_on.at(s).gate_shift_bearing_rad == 0);
    CHECK(st_on.at(s).gate_shift_range_m == 0);
    CHECK(found_share(sc, on, s) >= 0.85);
  }
  check_same(on, no, st_on, st_off);
}

TEST_CASE("multi association: the associated bearings and ranges stay the raw measurements") {
  Bias b;
  b.radar_bearing_rad = 5 * kDegToRad;
  b.radar_range_m = 40;
  b.eo_bearing_rad = 6 * kDegToRad;
  const Scene sc = make(14, b);
  std::map<std::string, SensorAssociation> st;
  const auto a = associate(sc.data, AssociationOptions{}, st);
  REQUIRE(st.at("radar").gate_shift_bearing_rad != 0);
  REQUIRE(st.at("eo").gate_shift_bearing_rad != 0);
  // every row's measurements per scan (sensor, t_s)
  std::multimap<std::pair<std::string, double>, std::pair<double, double>> rows;
  for (const auto& r : sc.data.detections) rows.insert({{r.sensor, r.t_s}, {r.bearing_rad, r.range_m}});
  std::map<std::string, std::vector<double>> db;  // per sensor: stored bearing minus reference bearing [rad]
  std::vector<double> dr;                         // radar: stored range minus reference range [m]
  int raw = 0, own_target = 0;
  for (const auto& x : a) {
    // bit for bit one row's measurements (a clutter row now and then, nearer the gate's centre)
    bool is_row = false;
    const auto span = rows.equal_range({x.sensor, x.t_s});
    for (auto it = span.first; it != span.second; ++it)
      is_row |= it->second.first == x.bearing_rad && (!x.has_range || it->second.second == x.range_m);
    raw += is_row;
    const auto it = sc.targets.find(Key{x.sensor, x.t_s, x.target});
    if (it == sc.targets.end() || it->second.bearing_rad != x.bearing_rad) continue;
    ++own_target;
    db[x.sensor].push_back(wrap_pi(x.bearing_rad - x.bearing_pred()));
    if (x.has_range) dr.push_back(x.range_m - x.range_pred());
  }
  CHECK(raw == static_cast<int>(a.size()));
  REQUIRE(own_target > 1000);
  // the raw residuals carry the whole bias (the geometry is the reference's, not the shifted gate's)
  CHECK(std::abs(median(db.at("radar")) - b.radar_bearing_rad) < 0.5 * kDegToRad);
  CHECK(std::abs(median(db.at("eo")) - b.eo_bearing_rad) < 0.5 * kDegToRad);
  CHECK(std::abs(median(dr) - b.radar_range_m) < 5);  // [m]
}

TEST_CASE("multi association: too few unambiguous pairs apply no shift, and the options are checked") {
  Bias b;
  b.eo_bearing_rad = 6 * kDegToRad;
  const Scene sc = make(15, b);
  AssociationOptions few;
  few.recentre_min_pairs = 1000000;  // more than the data hold
  std::map<std::string, SensorAssociation> st_few, st_off;
  const auto a = associate(sc.data, few, st_few);
  CHECK(st_few.at("eo").gate_shift_bearing_rad == 0);
  CHECK(st_few.at("eo").wide_pairs > 0);
  check_same(a, associate(sc.data, off(), st_off), st_few, st_off);
  std::map<std::string, SensorAssociation> st;
  AssociationOptions o;
  o.wide_gate_bearing_deg = 0;
  CHECK_THROWS_WITH(associate(sc.data, o, st), Catch::Contains("wide_gate_bearing_deg"));
  o = AssociationOptions{};
  o.wide_gate_position_m = -1;
  CHECK_THROWS_WITH(associate(sc.data, o, st), Catch::Contains("wide_gate_position_m"));
  o = AssociationOptions{};
  o.recentre_min_pairs = 2;
  CHECK_THROWS_AS(associate(sc.data, o, st), ConfigError);
  o.recentre_gates = false;  // the recentring options are not used, nor checked
  CHECK_NOTHROW(associate(sc.data, o, st));
}

TEST_CASE("reference interpolation: a track bending off the chord by a b / 2, and its acceleration") {
  // p(t) = (a t^2 / 2 north, 0 east), sampled every 10 s: the chord between t_a and t_b misses it
  // by a (t - t_a)(t_b - t) / 2, and every second difference is a (on the north axis alone: RMS
  // per axis a / sqrt(2)). Tolerances: the geodetic round trip (nanometres), not the model.
  constexpr double kAccel = 0.2, kDt = 10;  // [m/s^2], [s]
  const LocalLevelFrame F(Geodetic{63.44, 10.40, 0}, 0.0);
  std::vector<GeoSample> v;
  for (int k = 0; k <= 10; ++k) {
    const double t = k * kDt;
    v.push_back({t, F.to_geodetic(Eigen::Vector3d(0.5 * kAccel * t * t, 0, 0))});
  }
  const PlaneSeries s(v, F, 12);
  CHECK(s.accel_rms() == Approx(kAccel / std::sqrt(2.0)).epsilon(1e-6));
  double b = -1, interval = -1;
  REQUIRE(s.bridge(33, b, interval));
  CHECK(b == Approx(21));  // (33 - 30)(40 - 33)
  CHECK(interval == Approx(kDt));
  Eigen::Vector2d p;
  REQUIRE(s.at(33, p));
  CHECK(p.x() - 0.5 * kAccel * 33 * 33 == Approx(kAccel * b / 2).margin(1e-6));
  REQUIRE(s.bridge(30, b, interval));
  CHECK(b == 0);
  const PlaneSeries gappy(v, F, 5);  // 10 s between samples: nothing interpolated, no acceleration
  CHECK_FALSE(gappy.bridge(33, b, interval));
  CHECK(gappy.accel_rms() == 0);
}

TEST_CASE("multi association: each detection carries its reference's interpolation sd") {
  const Scene sc = make(21, Bias{});
  AssociationOptions o;
  o.reference_accel_mps2 = 1;  // [m/s^2]: sd = b / 2 with the 0.2 s references, b <= 0.01 s^2
  std::map<std::string, SensorAssociation> st;
  const auto a = associate(sc.data, o, st);
  REQUIRE(!a.empty());
  double most = 0;
  for (const auto& x : a) {
    CHECK(x.ref_interval_s == Approx(kTruthDtS));
    CHECK(x.ref_interp_sd_m >= 0);
    CHECK(x.ref_interp_sd_m <= 0.5 * 0.25 * kTruthDtS * kTruthDtS + 1e-12);
    most = std::max(most, x.ref_interp_sd_m);
  }
  CHECK(most > 0);  // the radar's 1.7 s scans fall between reference samples
  o.reference_accel_mps2 = -2;
  CHECK_THROWS_WITH(associate(sc.data, o, st), Catch::Contains("reference_accel_mps2"));
}

TEST_CASE("multi association: a unit mixed up is named before any gate", "[multisensor][input]") {
  std::map<std::string, SensorAssociation> st;
  SECTION("radar ranges in kilometres") {
    Scene sc = make(31, Bias{});
    for (auto& d : sc.data.detections)
      if (d.sensor == "radar" && std::isfinite(d.range_m)) d.range_m /= 1000;
    CHECK_THROWS_WITH(associate(sc.data, AssociationOptions{}, st),
                      Catch::Contains("detections.csv range_m of sensor radar looks like kilometres: median ratio"));
  }
  SECTION("radar ranges in feet") {
    Scene sc = make(32, Bias{});
    for (auto& d : sc.data.detections)
      if (d.sensor == "radar" && std::isfinite(d.range_m)) d.range_m /= 0.3048;
    CHECK_THROWS_WITH(associate(sc.data, AssociationOptions{}, st), Catch::Contains("range_m of sensor radar looks like feet"));
  }
  SECTION("camera bearings in radians written as degrees") {
    Scene sc = make(33, Bias{});
    for (auto& d : sc.data.detections)
      if (d.sensor == "eo" && std::isfinite(d.bearing_rad)) {
        const double b = d.bearing_rad < 0 ? d.bearing_rad + 2 * M_PI : d.bearing_rad;  // bearing_deg in [0, 360)
        d.bearing_rad = b * kDegToRad;                                                   // its radians read as degrees
      }
    CHECK_THROWS_WITH(associate(sc.data, AssociationOptions{}, st),
                      Catch::Contains("detections.csv bearing_deg of sensor eo looks like radians"));
  }
  SECTION("a 5 deg radar bearing bias and a 40 m range bias are effects, not units") {
    Bias b;
    b.radar_bearing_rad = 5 * kDegToRad;
    b.radar_range_m = 40;
    CHECK_NOTHROW(associate(make(34, b).data, AssociationOptions{}, st));
  }
}

TEST_CASE("reference jumps: a GNSS jump is found, a hard turn is not, and the longest stretch is kept") {
  // A boat at 3 m/s turning at up to 2 m/s^2 (a 4.5 m radius: harder than any boat of the Autoferry
  // data), its reference sampled at 25 Hz with 5 cm white noise per axis. The bound at the 0.5 s
  // half-span is 5 * 0.25 / 2 + 6 * scatter = about 0.9 m: a turn at 2 m/s^2 bends 0.25 m off the
  // chord, so it cannot be flagged unless the check is wrong; a 3 m jump is 3 m off for the
  // samples beside it.
  constexpr double kRate = 25, kSpan = 200, kSpeed = 3, kNoise = 0.05;  // [Hz], [s], [m/s], [m]
  constexpr double kTurnAccel = 2;                                      // [m/s^2] in the turns
  const LocalLevelFrame F(Geodetic{63.44, 10.40, 0}, 0.0);
  auto track = [&](double jump_t, double jump_m, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> N(0, kNoise);
    std::vector<GeoSample> v;
    Eigen::Vector2d p(0, 0);
    double heading = 0;
    const double dt = 1 / kRate;
    for (int k = 0; k * dt <= kSpan; ++k) {
      const double t = k * dt;
      // turning in [60, 75) s and [130, 140) s at omega = a / v
      const double omega = ((t >= 60 && t < 75) || (t >= 130 && t < 140)) ? kTurnAccel / kSpeed : 0.0;
      heading += omega * dt;
      p += kSpeed * dt * Eigen::Vector2d(std::cos(heading), std::sin(heading));
      const Eigen::Vector2d q = p + Eigen::Vector2d(N(rng), N(rng)) + Eigen::Vector2d(0, t >= jump_t ? jump_m : 0.0);
      v.push_back({t, F.to_geodetic(Eigen::Vector3d(q.x(), 0, q.y()))});
    }
    return v;
  };
  const ReferenceJumpOptions o;
  SECTION("no jump: the whole track, turns included") {
    const auto v = track(1e9, 0, 7);
    const ReferenceIntegrity ri = check_reference_jumps(v, F, o);
    CHECK(ri.jumps.empty());
    CHECK(ri.samples_used == v.size());
    CHECK(ri.used_from_s == 0);
    CHECK(ri.used_to_s == v.back().t_s);
  }
  SECTION("a 3 m jump at 150 s: found there, the stretch before it kept") {
    const auto v = track(150, 3, 7);
    const ReferenceIntegrity ri = check_reference_jumps(v, F, o);
    REQUIRE(ri.jumps.size() == 1);
    CHECK(std::abs(ri.jumps[0].t_s - 150) <= 1 / kRate);  // midway between the flags: within a sample
    CHECK(ri.jumps[0].deviation_m > ri.jumps[0].bound_m);
    CHECK(ri.used_from_s == 0);
    CHECK(ri.used_to_s < 150);
    // untrusted from half a span before the first flagged sample, whose chord reaches at most
    // half a span and one sample interval across the jump
    CHECK(ri.used_to_s >= 150 - 2 * o.half_span_s - 1 / kRate);
    CHECK(ri.samples_used < v.size());
  }
  SECTION("a 3 m jump at 40 s: the longer stretch after it kept") {
    const auto v = track(40, 3, 7);
    const ReferenceIntegrity ri = check_reference_jumps(v, F, o);
    REQUIRE(ri.jumps.size() == 1);
    CHECK(ri.used_from_s > 40);
    CHECK(ri.used_from_s <= 40 + 2 * o.half_span_s + 1 / kRate);
    CHECK(ri.used_to_s == v.back().t_s);
  }
  SECTION("options are checked") {
    ReferenceJumpOptions bad;
    bad.max_accel_mps2 = 0;
    CHECK_THROWS_WITH(check_reference_jumps(track(1e9, 0, 7), F, bad), Catch::Contains("max_accel_mps2"));
  }
}

TEST_CASE("multi association: detections scored against a reference that jumped are not associated") {
  // Target 1's reference jumps 8 m east at 150 s (inside the 20 m gate, so without the check the
  // radar's detections after it would be associated, 8 m off); its detections do not move.
  constexpr double kJumpS = 150, kJumpM = 8;
  const Scene sc = make(31, Bias{}, RefJump{kJumpS, kJumpM});
  std::map<std::string, SensorAssociation> st;
  std::map<std::string, ReferenceIntegrity> jumps;
  const auto a = associate(sc.data, AssociationOptions{}, st, &jumps);
  REQUIRE(jumps.size() == 1);
  REQUIRE(jumps.count("1") == 1);
  CHECK(std::abs(jumps.at("1").jumps.at(0).t_s - kJumpS) <= kTruthDtS);  // within a reference interval
  int after = 0, before = 0;
  for (const auto& x : a)
    if (x.target == "1") (x.t_s >= kJumpS ? after : before)++;
  CHECK(after == 0);
  CHECK(before > 100);
  AssociationOptions off_check;
  off_check.reference_jump_accel_mps2 = 0;
  std::map<std::string, SensorAssociation> st2;
  const auto b = associate(sc.data, off_check, st2);
  int after_off = 0;
  for (const auto& x : b)
    if (x.target == "1" && x.sensor == "radar" && x.t_s >= kJumpS) ++after_off;
  CHECK(after_off > 10);  // the 8 m offset inside the gate: associated without the check
  off_check.reference_jump_accel_mps2 = -1;
  CHECK_THROWS_WITH(associate(sc.data, off_check, st2), Catch::Contains("reference_jump_accel_mps2"));
}

TEST_CASE("multi association: references without jumps associate exactly as without the check") {
  const Scene sc = make(32, Bias{});
  std::map<std::string, SensorAssociation> sa, sb;
  std::map<std::string, ReferenceIntegrity> jumps;
  AssociationOptions no_check;
  no_check.reference_jump_accel_mps2 = 0;
  const auto a = associate(sc.data, AssociationOptions{}, sa, &jumps);
  CHECK(jumps.empty());
  check_same(a, associate(sc.data, no_check, sb), sa, sb);
}

TEST_CASE("reference jumps: on the nine Autoferry recordings one track jumps, and the limit measured by injection",
          "[multisensor][autoferry][real]") {
  // The 18 GNSS tracks of the nine recordings (Havfruen at 25 Hz, Gunnerus and the jetboat at
  // 5 Hz, both thinned to the samples the dataset used). Only Havfruen's in scenario 6 jumps
  // (docs/autoferry-multi-sensor.md). Into each of the 17 others a step of J metres is injected
  // (direction and time uniform, in the middle 80 % of the track, fixed seed), kInjections per
  // track and size; found = exactly one jump reported, within one half-span of the step.
  // Measured (kInjections = 10, 170 per size): 0.5 m 0 %, 1 m 86 %, 1.25 m and above 100 % (a
  // step of J is about J / 2 off the chord beside it; the bound is 0.16 m of acceleration plus six
  // sds of the track's scatter, 0.4-0.5 m on the 25 Hz tracks). Asserted: none of the 17 clean
  // tracks jumps (no false alarm), and at 1.25 m at least 90 % of the 170 steps are found (the
  // docs' limit: 153 of 170).
  const std::string data = std::string(RNAV_DATA_DIR) + "/autoferry";
  if (!std::filesystem::exists(data)) FAIL("the Autoferry recordings are not at " << data);
  constexpr int kInjections = 10;
  const double sizes_m[] = {0.5, 1.0, 1.25, 1.5, 2.0};
  const ReferenceJumpOptions o;
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> U(0, 1);
  std::map<double, int> found;  // per size
  int clean = 0, tracks = 0;
  for (int sc : {2, 3, 4, 5, 6, 13, 16, 17, 22}) {
    const MultiSensorData d = autoferry_to_multi(load_autoferry(data + "/scenario" + std::to_string(sc)));
    const LocalLevelFrame F(d.observer.front().g, 0.0);
    for (const auto& [name, v] : d.truth_on_level()) {
      ++tracks;
      const ReferenceIntegrity ri = check_reference_jumps(v, F, o);
      INFO("scenario " << sc << " target " << name);
      if (sc == 6 && name == "1") {  // Havfruen's jump at 88.9 s after its first sample
        REQUIRE(ri.jumps.size() == 1);
        CHECK(std::abs(ri.jumps[0].t_s - v.front().t_s - 88.9) < 0.5);
        continue;
      }
      CHECK(ri.jumps.empty());
      ++clean;
      const double t0 = v.front().t_s, span = v.back().t_s - t0;
      for (double J : sizes_m)
        for (int k = 0; k < kInjections; ++k) {
          const double t_step = t0 + span * (0.1 + 0.8 * U(rng)), dir = 2 * M_PI * U(rng);
          const Eigen::Vector3d step(J * std::cos(dir), 0, J * std::sin(dir));
          std::vector<GeoSample> w = v;
          for (auto& x : w)
            if (x.t_s >= t_step) x.g = F.to_geodetic(F.from_geodetic(x.g) + step);
          const ReferenceIntegrity rj = check_reference_jumps(w, F, o);
          found[J] += rj.jumps.size() == 1 && std::abs(rj.jumps[0].t_s - t_step) <= o.half_span_s;
        }
    }
  }
  CHECK(tracks == 18);
  CHECK(clean == 17);
  for (double J : sizes_m)
    std::cout << "reference jump of " << J << " m injected into the 17 clean Autoferry tracks: found in " << found[J]
              << " of " << clean * kInjections << "\n";
  CHECK(found[1.25] >= 153);
}

TEST_CASE("multi association: a gate shift beyond what its sensor can be off by is refused and named",
          "[multisensor][autoferry][real][input]") {
  // Autoferry scenario 4 with the EO camera's bearings turned by 18 deg (inside the 20 deg
  // first-pass gate): the fitted shift (about 16 deg) is beyond what a bearing-only sensor can be
  // off by (15 deg, 5 s: multi_association.cpp's shift_bounds), so it is refused, named, and the
  // gates stay on the prediction; turned by 10 deg, the gates are recentred and nothing is
  // refused; as recorded, no sensor's shift is refused. (A fit that far off comes from pairs that
  // are not the targets': Havfruen's echoes after her reference was cut at mid-span moved the
  // lidar's gates by 40 deg and -60 m, before the uncovered stretch was left out.)
  const MultiSensorData whole = autoferry_scenario4();
  const AssociationOptions o;
  auto turned = [&](double deg) {
    MultiSensorData d = whole;
    for (Detection& x : d.detections)
      if (x.sensor == "eo" && !x.empty_scan()) x.bearing_rad = std::remainder(x.bearing_rad + deg * M_PI / 180, 2 * M_PI);
    std::map<std::string, SensorAssociation> st;
    associate(d, o, st);
    REQUIRE(st.count("eo") == 1);
    return st.at("eo");
  };
  std::map<std::string, SensorAssociation> plain;
  associate(whole, o, plain);
  for (const auto& [sensor, st] : plain) {
    INFO("sensor " << sensor << ": " << st.shift_refused);
    CHECK(st.shift_refused.empty());
  }
  const SensorAssociation far = turned(18);
  INFO("eo turned by 18 deg: " << far.shift_refused);
  CHECK(far.shift_refused.find("beyond what a bearing-only sensor can be off by") != std::string::npos);
  CHECK(far.gate_shift_bearing_rad == 0);
  CHECK(far.gate_shift_clock_s == 0);
  const SensorAssociation near = turned(10);
  INFO("eo turned by 10 deg: " << near.shift_refused << ", shift " << near.gate_shift_bearing_rad * 180 / M_PI << " deg");
  CHECK(near.shift_refused.empty());
  CHECK(near.gate_shift_bearing_rad > 5 * M_PI / 180);
}

TEST_CASE("multi diagnosis: a reference that ends mid-recording: the uncovered part is left out and named, the covered "
          "part diagnosed as that part alone",
          "[multisensor][autoferry][real][input]") {
  // Autoferry scenario 4, Havfruen's (target 1's) reference cut at the middle of its span. Every
  // scan after the cut is left out for every target (her echoes there would be taken for the
  // Gunnerus's or for clutter), the report names the stretch and what it left out, and the
  // diagnosis of what is left equals, within 2 standard errors, that of the recording cut at the
  // same time (observer, detections and references): the IR camera's bearing bias. Before, the
  // lidar's gates moved by 40 deg and the report named a 41.8 deg lidar bearing bias.
  const MultiSensorData whole = autoferry_scenario4();
  const std::vector<GeoSample>& ref = whole.truth.at("1");
  const double mid = 0.5 * (ref.front().t_s + ref.back().t_s);
  MultiSensorData cut = whole, half = whole;
  auto after = [mid](const auto& x) { return x.t_s > mid; };
  auto& v = cut.truth["1"];
  v.erase(std::remove_if(v.begin(), v.end(), after), v.end());
  half.detections.erase(std::remove_if(half.detections.begin(), half.detections.end(), after), half.detections.end());
  half.observer.erase(std::remove_if(half.observer.begin(), half.observer.end(), after), half.observer.end());
  for (auto& [name, w] : half.truth) w.erase(std::remove_if(w.begin(), w.end(), after), w.end());

  const MultiDiagnoseOptions o;
  const MultiReport rc = diagnose_multi(cut, o), rh = diagnose_multi(half, o);
  REQUIRE(rc.reference_jumps.count("1") == 1);
  const ReferenceIntegrity& ri = rc.reference_jumps.at("1");
  REQUIRE(ri.uncovered.size() == 1);
  CHECK(std::abs(ri.uncovered[0].first - v.back().t_s) < 1e-9);
  CHECK(ri.uncovered[0].second == ri.detections_to_s);
  CHECK(ri.detections_left_out > 1000);
  CHECK(rc.text().find("reference 1: does not cover") != std::string::npos);
  CHECK(rh.reference_jumps.empty());
  for (const auto& e : rc.result.effects) {
    INFO(e.name << " " << e.scope.label());
    CHECK(!(e.name == "bearing_bias" && e.scope.sensor == "lidar"));
  }
  auto ir_bias = [](const MultiReport& r) -> const FoundEffect* {
    for (const auto& e : r.result.effects)
      if (e.name == "bearing_bias" && e.scope.sensor == "ir") return &e;
    return nullptr;
  };
  const FoundEffect *a = ir_bias(rc), *b = ir_bias(rh);
  REQUIRE(a != nullptr);
  REQUIRE(b != nullptr);
  INFO("IR bearing bias: covered part " << a->estimate[0] << " +- " << a->stderr_[0] << ", the recording cut there "
                                        << b->estimate[0] << " +- " << b->stderr_[0]);
  CHECK(std::abs(a->estimate[0] - b->estimate[0]) < 2 * std::hypot(a->stderr_[0], b->stderr_[0]));
}

TEST_CASE("multi association: references stamped late against the detections are named with the shift",
          "[multisensor][autoferry][real][input]") {
  // Autoferry scenario 4 with every reference sample stamped 20 s (and 30 s) late: the lidar's
  // ranges then miss the geometry (median ratio 0.69) and the unit check refuses the recording.
  // The error must say that a time shift explains it and give its size. The lidar stamps its
  // scans late by its own clock (0.76 s in the pooled diagnosis of the nine recordings), so the
  // shift that aligns its ranges is the stamping minus that clock: each found shift lies within
  // 1 s of the stamping, and the two differ by the 10 s between them to within 0.2 s (twice the
  // search's fine step of 0.1 s; the lidar's clock cancels). Stamped 0.7 s late, the check passes.
  const MultiSensorData whole = autoferry_scenario4();
  auto shifted = [&](double late_s) {
    MultiSensorData d = whole;
    for (auto& [name, v] : d.truth)
      for (GeoSample& g : v) g.t_s += late_s;
    return d;
  };
  const AssociationOptions o;
  std::map<std::string, SensorAssociation> st;
  const std::string lead = "a time shift explains it: with truth.csv's times moved by ";
  auto found_shift = [&](double late_s) {
    std::string what;
    try {
      associate(shifted(late_s), o, st);
    } catch (const ConfigError& e) {
      what = e.what();
    }
    INFO(what);
    REQUIRE(what.find("does not match the reference geometry") != std::string::npos);
    const auto at = what.find(lead);
    REQUIRE(at != std::string::npos);
    CHECK(what.find("late against detections.csv") != std::string::npos);
    return -std::stod(what.substr(at + lead.size()));
  };
  const double s20 = found_shift(20), s30 = found_shift(30);
  INFO("found " << s20 << " s and " << s30 << " s");
  CHECK(std::abs(s20 - 20) < 1);
  CHECK(std::abs(s30 - 30) < 1);
  CHECK(std::abs((s30 - s20) - 10) < 0.2);
  CHECK_NOTHROW(associate(shifted(0.7), o, st));
}

TEST_CASE("multi association: references of another place are named as far from the observer, not as a range unit",
          "[multisensor][autoferry][real][input]") {
  // Autoferry scenario 4 with the observer's track moved 100 km north (0.9 deg of latitude):
  // every target's reference lies 100 km away while the radar and lidar see nothing beyond 0.5
  // km (the diagnosis said only "no detection associated to any target"). The error must say that
  // the references lie far from the observer, with the nearest target's distance (100 km to
  // within 5 km: the boats move a few hundred metres about the ferry), and must not name a unit.
  const MultiSensorData whole = autoferry_scenario4();
  auto moved = [&](double north_deg) {
    MultiSensorData d = whole;
    for (GeoSample& g : d.observer) g.g.lat_deg += north_deg;
    return d;
  };
  const AssociationOptions o;
  std::map<std::string, SensorAssociation> st;
  std::string what;
  try {
    associate(moved(0.9), o, st);
  } catch (const ConfigError& e) {
    what = e.what();
  }
  INFO(what);
  CHECK(what.find("looks like") == std::string::npos);
  const std::string lead = "the references lie far from the observer: the nearest target (";
  const auto at = what.find(lead);
  REQUIRE(at != std::string::npos);
  const auto km_at = what.find(") at a median ", at);
  REQUIRE(km_at != std::string::npos);
  const double km = std::stod(what.substr(km_at + std::string(") at a median ").size()));
  CHECK(std::abs(km - 100) < 5);
}
