// The recorded-scene simulation (sim/scene) and its validation (scripts/compose/scene): the
// effect columns' geometry against finite differences of the scene's own line of sight; the
// same seed the same detections, whatever the thread count; a report read as errors, bad ones
// named; and the loop the tool exists for: an effect hidden in a recording (a generator of
// this file's own), diagnosed, its extended scene simulated, and the recording inside the
// simulated band with the effect and outside it without.
#include "common/io/config.hpp"
#include "estimators/diagnosis/multi_diagnose.hpp"
#include "scripts/compose/scene/scene_effects_json.hpp"
#include "scripts/compose/scene/scene_from_recording.hpp"
#include "sim/scene/scene_geometry.hpp"
#include "sim/scene/scene_sim.hpp"
#include "scripts/compose/scene/scene_validation.hpp"
#include "test/scene_recording_gen.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace rnav;
using namespace rnav_test::scene_gen;

namespace {

AssociationOptions assoc() {
  AssociationOptions o;
  o.gate_position_m = 30;
  return o;
}

}  // namespace

TEST_CASE("scene geometry: the effect columns are the line of sight's own derivatives") {
  const MultiSensorData d = recording(1, 0);
  const auto& tr = d.truth.at("1");
  const double t = 100, h = 1e-3;
  scene::LineOfSight a, b, c;
  REQUIRE(scene::line_of_sight(d.observer, tr, t, 2, a));
  REQUIRE(scene::line_of_sight(d.observer, tr, t - h, 2, b));
  REQUIRE(scene::line_of_sight(d.observer, tr, t + h, 2, c));
  // the sensor clock: y(t - tau) - y(t) = -(dy/dt) tau, the column -dh v_rel
  for (const bool is_range : {false, true}) {
    const auto g = scene::effect_geometry(a, is_range, t, 0.5);
    const double dydt = is_range ? (c.range_m - b.range_m) / (2 * h) : wrap_pi(c.bearing_rad - b.bearing_rad) / (2 * h);
    const double col = multi_effect::sensor_clock(g)(0);
    INFO((is_range ? "range" : "bearing") << " rate " << dydt << " column " << col);
    // each line of sight in the tangent plane at the observer then: the generator's straight
    // tracks (in the tangent plane at its origin, 100 m away) bend by about 1e-5 in it; a wrong
    // column is wrong by O(1): 1e-4 relative
    CHECK(std::abs(col + dydt) < 1e-4 * std::abs(dydt));
  }
  // the hull offset: moving the target 1 m along its course changes y by dh u
  const auto gb = scene::effect_geometry(a, false, t, 0.5);
  const Eigen::Vector2d d1 = a.d + gb.u;
  const double db = wrap_pi(std::atan2(d1.x(), d1.y()) - a.bearing_rad);
  CHECK(std::abs(multi_effect::hull_offset(gb)(0) - db) < 5e-3 * std::abs(db));  // second order: 1 m against about 400 m
  // the course: boat 1 runs (3, -1.5) m/s, so u is that direction and u_perp its starboard
  INFO("u " << gb.u.transpose() << " u_perp " << gb.u_perp.transpose() << " v " << a.v_target.transpose());
  CHECK(gb.u.isApprox(Eigen::Vector2d(3, -1.5).normalized(), 1e-4));
  CHECK(gb.u_perp.isApprox(Eigen::Vector2d(-1.5, -3).normalized(), 1e-4));
}

TEST_CASE("scene simulation: the same seed the same detections, any thread count the same statistics") {
  const MultiSensorData d = recording(2, kRadarBiasRad);
  scene::RecordedScene sc = scene_from_recording(d, "rec", assoc());
  const auto err = nominal_errors(0.3 * kDegToRad, 2);
  calibrate_detection(sc, d, err, assoc(), 1);
  const auto a = scene::simulate(sc, err, 7, 3), b = scene::simulate(sc, err, 7, 3), c = scene::simulate(sc, err, 7, 4);
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK((a[i].t_s == b[i].t_s && a[i].sensor == b[i].sensor && a[i].target == b[i].target));
    CHECK((std::isnan(a[i].bearing_rad) ? std::isnan(b[i].bearing_rad) : a[i].bearing_rad == b[i].bearing_rad));
  }
  bool differs = a.size() != c.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) differs = a[i].bearing_rad != c[i].bearing_rad;
  CHECK(differs);
  // every scan of the recording is a scan of the simulation (empty ones kept)
  std::map<std::string, std::set<double>> scans_real, scans_sim;
  for (const auto& x : d.detections) scans_real[x.sensor].insert(x.t_s);
  for (const auto& x : a) scans_sim[x.sensor].insert(x.t_s);
  CHECK(scans_real == scans_sim);
  const auto s1 = simulated_stats(d, sc, err, assoc(), 6, 1, 1), s2 = simulated_stats(d, sc, err, assoc(), 6, 1, 2);
  for (std::size_t k = 0; k < s1.size(); ++k)
    for (const auto& [ch, x] : s1[k].residuals) CHECK(x.mean == s2[k].residuals.at(ch).mean);
}

TEST_CASE("scene simulation: a radar that stamps each return at its own time is simulated by rotations, each return lit by the beam") {
  // The recording's radar stamps each return when its beam lights it (a ship radar's way; period
  // 2 s, clockwise, kBeamB0Rad at t = 0). Read as stamped, every return would be a scan of its
  // own: the simulation would make a target's returns at the recorded stamps of other targets'
  // and clutter's returns, and its detection rate per scan a third of the recording's.
  const MultiSensorData d = recording(4, 0.0, 0.0, true);
  scene::RecordedScene sc = scene_from_recording(d, "rec", assoc());
  const scene::SceneSensor* radar = nullptr;
  for (const auto& s : sc.sensors)
    if (s.name == "radar") radar = &s;
  REQUIRE(radar != nullptr);
  const scene::Rotation& r = radar->rotation;
  REQUIRE(r.rotating());
  // the beam's phase and rate fitted together by least squares on ~360 returns with 0.3 deg
  // noise (the boats' and the clutter's): the phase's SE about 0.03 deg, the bound 0.2 deg; the
  // period's SE about 1e-6 of it, the bound 1e-3 (a period off by 1e-3 would turn the fitted
  // beam 43 deg off over the 240 s, which the phase bound would catch as well)
  CHECK(r.direction == 1);
  CHECK(std::abs(r.period_s - kBeamPeriodS) < 1e-3 * kBeamPeriodS);
  const double b0_true = wrap_pi(kBeamB0Rad + 2 * M_PI * r.t0_s / kBeamPeriodS);
  CHECK(std::abs(wrap_pi(r.b0_rad - b0_true)) < 0.2 * kDegToRad);
  CHECK(std::abs(radar->scan_period_s - r.period_s) < 1e-12);
  // noise-free simulation: each target return's bearing is where the fitted beam points then
  const auto quiet = nominal_errors(1e-9, 1e-6);
  const auto sim = scene::simulate(sc, quiet, 3, 0);
  std::map<std::string, int> returns;
  double worst = 0, last_t = -1;
  bool sorted = true, empty_scan = false;
  for (const auto& x : sim) {
    if (x.sensor != "radar") continue;
    sorted = sorted && x.t_s >= last_t;
    last_t = x.t_s;
    empty_scan = empty_scan || std::isnan(x.bearing_rad);
    if (x.target.empty()) continue;
    ++returns[x.target];
    const double beam = r.b0_rad + r.direction * 2 * M_PI * (x.t_s - r.t0_s) / r.period_s;
    worst = std::max(worst, std::abs(wrap_pi(x.bearing_rad - beam)));
  }
  CHECK(sorted);
  CHECK_FALSE(empty_scan);
  CHECK(worst < 1e-6);  // the fixed point converged: microradians, not the beam's 3 deg per 1/60 s
  const double rotations = std::floor((d.detections.back().t_s - r.t0_s) / r.period_s) + 1;
  for (const char* t : {"1", "2"}) {
    INFO("target " << t);
    CHECK(returns[t] >= 0.9 * rotations);  // p_d 1 before calibration: each rotation lights it (rarely twice or none at the cut)
    CHECK(returns[t] <= rotations + 2);
  }
  // calibrated, the detection rate per rotation is the recording's: inside the band
  const auto err = nominal_errors(0.3 * kDegToRad, 2);
  calibrate_detection(sc, d, err, assoc(), 1);
  const auto rows = validation_rows("rec", "nominal", scene_stats(d, assoc()), simulated_stats(d, sc, err, assoc(), 30, 1, 2));
  int rate_rows = 0;
  for (const auto& row : rows)
    if (row.pair.rfind("radar:", 0) == 0 && row.statistic == "detection_rate") {
      INFO(row.pair << " real " << row.real << " band " << row.band_lo << " .. " << row.band_hi);
      CHECK(row.inside);
      ++rate_rows;
    }
  CHECK(rate_rows == 2);
}

TEST_CASE("scene errors: a report's effects and noise are read, and a bad report is named") {
  nlohmann::json j = {{"kind", "multi"},
                      {"effects",
                       {{{"name", "bearing_bias"}, {"scope", {{"sensor", "radar"}, {"target", nullptr}}}, {"estimate", 0.02}},
                        {{"name", "antenna_offset"}, {"scope", {{"sensor", nullptr}, {"target", "1"}}}, {"estimate", {-3.0, 0.5}}},
                        {{"name", "target_maneuver"}, {"scope", {{"target", "1"}}}, {"estimate", {10.0, 0.1, 0.2}}}}},
                      {"noise",
                       {{"radar:1:bearing",
                         {{"sigma", 0.01}, {"correlated_share", 0.999}, {"tau_s", 20.0}, {"outlier_fraction", 0.02}, {"outlier_sd", 0.05},
                          {"noise_scale", 2.0}}}}}};
  const auto e = errors_from_report(j, "r.json", "rec", 0.1, 1);
  REQUIRE(e.effects.size() == 2);  // the manoeuvre is the reference's own
  CHECK(e.effects[1].theta == std::vector<double>{-3.0, 0.5});
  CHECK(e.noise.at("radar:1:bearing").tau_s == 20.0);
  CHECK(e.nominal_bearing_sigma_rad == Approx(0.005));  // 0.01 over its noise scale 2
  auto bad = j;
  bad["effects"][0]["name"] = "bearing_bais";
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("effects[0]") && Catch::Contains("bearing_bais"));
  bad = j;
  bad["noise"]["radar:1:bearing"].erase("outlier_sd");
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("outlier_sd"));
  bad = j;
  bad["effects"][1]["estimate"] = {1.0};
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("antenna_offset") && Catch::Contains("2 parameter"));
  bad = j;
  bad["kind"] = "prl";
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("not a multi-sensor diagnosis report"));
}

TEST_CASE("scene errors: the targets' offsets of a report are drawn once per target and realization, not for a target its own effect explains") {
  nlohmann::json j = {{"kind", "multi"},
                      {"effects", nlohmann::json::array()},
                      {"offsets",
                       {{"radar:range", {{"unit", "m"}, {"mean", 10.0}, {"sd", 5.0}, {"explained", {"radar:2:range"}}}}}}};
  const auto e = errors_from_report(j, "r.json", "rec", 0.3 * kDegToRad, 2);
  REQUIRE(e.offsets.count("radar:range"));
  CHECK(e.offsets.at("radar:range").explained == std::set<std::string>{"radar:2:range"});
  // with the identified noise (use_simulated false) no offset is drawn: that noise is fitted
  // with a trend, not about each channel's own mean
  CHECK(errors_from_report(j, "r.json", "rec", 0.3 * kDegToRad, 2, false).offsets.empty());
  auto bad = j;
  bad["offsets"]["radar:range"]["sd"] = -1.0;
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("radar:range") && Catch::Contains("sd >= 0"));
  bad = j;
  bad["offsets"]["radar:range"].erase("mean");
  CHECK_THROWS_WITH(errors_from_report(bad, "r.json", "rec", 0.1, 1), Catch::Contains("offsets \"radar:range\"") && Catch::Contains("'mean'"));
  // Drawn: boat 1's range residual mean (raw, against its line of sight) over kRuns realizations
  // has mean 10 and sd 5 (each realization's own noise adds 2 m / sqrt(~110) = 0.2 m to the sd:
  // sqrt(25 + 0.04)); its mean lies within 3 SE (5 / sqrt(kRuns)) of 10, its sd within 3 SE
  // (5 / sqrt(2 kRuns)) of 5. Boat 2's, explained, draws none: its mean per realization is the
  // noise's alone (sd about 0.2 m): within 3 x 0.2 m of 0, and its sd below 0.5 m (a drawn
  // offset would make it 5 m).
  const MultiSensorData d = recording(5, 0.0);
  scene::RecordedScene sc = scene_from_recording(d, "rec", assoc());
  const int kRuns = 200;
  std::vector<double> m1, m2;
  for (int k = 0; k < kRuns; ++k) {
    std::map<std::string, std::vector<double>> raw;
    for (const auto& x : scene::simulate(sc, e, 11, static_cast<std::uint64_t>(k))) {
      scene::LineOfSight los;
      if (x.sensor != "radar" || x.target.empty() ||
          !scene::line_of_sight(sc.observer, sc.targets.at(x.target), x.t_s, sc.reference_max_gap_s, los))
        continue;
      raw[x.target].push_back(x.range_m - los.range_m);
    }
    m1.push_back(residual_stats(raw["1"]).mean);
    m2.push_back(residual_stats(raw["2"]).mean);
  }
  const auto s1 = residual_stats(m1), s2 = residual_stats(m2);
  INFO("boat 1: mean " << s1.mean << " sd " << s1.sd << "; boat 2: mean " << s2.mean << " sd " << s2.sd);
  CHECK(std::abs(s1.mean - 10) < 3 * 5 / std::sqrt(kRuns));
  CHECK(std::abs(s1.sd - 5) < 3 * 5 / std::sqrt(2.0 * kRuns));
  CHECK(std::abs(s2.mean) < 3 * 0.2);
  CHECK(s2.sd < 0.5);
}

TEST_CASE("scene validation: a hidden radar bias diagnosed, simulated, and the recording inside the band only with it") {
  const MultiSensorData d = recording(3, kRadarBiasRad);
  MultiDiagnoseOptions mo;
  mo.association = assoc();
  mo.sigma_bearing_deg = 0.3;
  mo.sigma_range_m = 2;
  const MultiReport rep = diagnose_multi(d, mo);
  INFO(rep.text());
  const auto ext = errors_from_report(nlohmann::json::parse(rep.to_json().dump()), "report", "rec", 0.3 * kDegToRad, 2);
  bool has_bias = false;
  for (const auto& e : ext.effects) has_bias = has_bias || (e.name == "bearing_bias" && e.sensor == "radar");
  REQUIRE(has_bias);
  const auto nom = nominal_errors(0.3 * kDegToRad, 2);
  const SceneStats real = scene_stats(d, assoc());
  const int runs = 60;
  auto rows_of = [&](const scene::SceneErrors& err, const std::string& model) {
    scene::RecordedScene sc = scene_from_recording(d, "rec", assoc());
    calibrate_detection(sc, d, err, assoc(), 1);
    return validation_rows("rec", model, real, simulated_stats(d, sc, err, assoc(), runs, 1, 2));
  };
  const auto ext_rows = rows_of(ext, "extended"), nom_rows = rows_of(nom, "nominal");
  auto find = [](const std::vector<ValidationRow>& rows, const std::string& pair, const std::string& q, const std::string& st) {
    for (const auto& r : rows)
      if (r.pair == pair && r.quantity == q && r.statistic == st) return r;
    FAIL("no row " << pair << " " << q << " " << st);
    return ValidationRow{};
  };
  for (const char* t : {"radar:1", "radar:2"}) {
    CHECK(find(ext_rows, t, "bearing", "mean").inside);
    CHECK_FALSE(find(nom_rows, t, "bearing", "mean").inside);  // 1.5 deg against a band of a few hundredths
  }
  // Under a right model each row falls outside its 5-95 % band with probability about 0.1
  // (estimated quantiles of 60 runs). Rows of one pair are not independent, but the count of
  // rows outside is at most that of 7 pairs' independent rows: its 99.9 % binomial bound
  // (n rows, p 0.1) is the pass mark. The hidden bias alone moves the nominal's radar means.
  int out = 0;
  for (const auto& r : ext_rows) out += !r.inside;
  const int n = static_cast<int>(ext_rows.size());
  // 99.9 % quantile of Binomial(n, 0.1): smallest k with P(X <= k) >= 0.999
  double cdf = 0, pk = std::pow(0.9, n);
  int bound = 0;
  for (int k = 0; k <= n; ++k) {
    cdf += pk;
    if (cdf >= 0.999) {
      bound = k;
      break;
    }
    pk *= (n - k) / static_cast<double>(k + 1) * (0.1 / 0.9);
  }
  INFO(out << " of " << n << " rows outside, bound " << bound);
  CHECK(out <= bound);
}
