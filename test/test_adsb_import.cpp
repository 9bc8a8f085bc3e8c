// Tests of the ADS-B importer (sim/trajectory/adsb_*.hpp): a synthetic flight written by the
// test with known approaches and injected glitches, input errors, and the real Vienna file.
#include "sim/trajectory/adsb_approaches.hpp"
#include "test/csv_units.hpp"
#include "sim/trajectory/replay_trajectory.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

constexpr double kFt = 0.3048;
const ApproachSearchOptions kRunway;  // default: our scenario's LOWW 29 threshold and heading

// A synthetic flight in the landing frame L of kRunway, sampled every 5 s at 75 m/s: two
// straight-in approaches on the centreline from x = 12 km (level at 600 m until the 3 deg glide
// path through 15 m over the threshold, down to x = 500 m), each followed by a climbing
// go-around to the side (course 90 deg off the runway) and a level downwind leg (the
// reciprocal course) back out. Heights: baro altitude = (WGS84 height) / 0.3048 exactly, so
// the fitted height offset must be 0 and the glide angle 3 deg.
nlohmann::json synthetic_flight(bool int8_track) {
  const LocalLevelFrame L(kRunway.threshold, std::fmod(kRunway.heading_deg + 180.0, 360.0));
  const double tan3 = std::tan(3 * kDegToRad), V = 75, dt = 5;
  // Waypoints (x, z) with the height rule; legs flown straight at V.
  struct Leg { Eigen::Vector2d a, b; int kind; };  // kind 0: approach profile, 1: climb 600->800 m, 2: level 800 m, 3: descend 800 -> 600 m
  std::vector<Leg> legs;
  for (int k = 0; k < 2; ++k) {
    legs.push_back({{12000, 0}, {500, 0}, 0});
    legs.push_back({{500, 0}, {500, 3000}, 1});
    legs.push_back({{500, 3000}, {12000, 3000}, 2});
    legs.push_back({{12000, 3000}, {12000, 0}, 3});
  }
  nlohmann::json doc = nlohmann::json::array();
  double t = 0;
  for (const auto& leg : legs) {
    const double len = (leg.b - leg.a).norm();
    for (double s = 0; s < len; s += V * dt, t += dt) {
      const Eigen::Vector2d p = leg.a + (leg.b - leg.a) * (s / len);
      double y = 0;
      if (leg.kind == 0) y = std::min(600.0, 15 + p.x() * tan3);
      if (leg.kind == 1) y = 15 + 500 * tan3 + (800 - 15 - 500 * tan3) * s / len;
      if (leg.kind == 2) y = 800;
      if (leg.kind == 3) y = 800 - 200 * s / len;
      const Geodetic g = L.to_geodetic({p.x(), y, p.y()});
      const Eigen::Vector2d d = (leg.b - leg.a).normalized();
      // true track of this leg: bearing of direction d in L (x at heading+180, z at heading+270)
      const double track = std::fmod(kRunway.heading_deg + 180 + std::atan2(d.y(), d.x()) / kDegToRad + 720, 360);
      const double stored = int8_track ? static_cast<double>(static_cast<std::int8_t>(static_cast<int>(std::lround(track)) & 0xff)) : track;
      doc.push_back({{"timestamp", 1542756885000LL + static_cast<long long>(t * 1000)},
                     {"latitude", g.lat_deg}, {"longitude", g.lon_deg},
                     {"altitude", g.h_m / kFt}, {"track", stored}, {"groundspeed", 146}});
    }
  }
  return doc;
}

std::vector<Approach> approaches(const nlohmann::json& doc, CleanTrack* clean_out = nullptr) {
  const auto rec = parse_adsb_records(doc.dump(), "synthetic");
  const CleanTrack c = remove_glitches(rec, GlitchOptions{}, "synthetic");
  if (clean_out) *clean_out = c;
  return find_approaches(c.kept, kRunway);
}

std::string error_of(const std::string& text) {
  try {
    parse_adsb_records(text, "f.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("synthetic flight: two approaches, exact glide angle and height offset", "[adsb]") {
  CleanTrack c;
  const auto a = approaches(synthetic_flight(false), &c);
  CHECK(c.removed_total() == 0);
  REQUIRE(a.size() == 2);
  // The first starts at the file's first point (x = 12 km; course one-sided); the second one
  // sample later, because the corner point's course (from its neighbours) is 45 deg off.
  CHECK(a[0].x_start_m == Approx(12000).margin(1e-3));
  CHECK(a[1].x_start_m == Approx(12000 - 375).margin(1e-3));
  for (const auto& ap : a) {
    // Each ends at its lowest point, the last sample before x = 500 m (x = 12000 - 375 k).
    CHECK(ap.x_end_m == Approx(12000 - 375 * 30).margin(1e-3));
    CHECK(std::abs(ap.lateral_mean_m) < 1e-3);
    CHECK(ap.lateral_rms_m < 1e-3);
    REQUIRE(ap.glide_deg.has_value());
    // The profile is exactly linear on the fitted part; the fit adds the offset after the
    // frame conversion, exact to 1e-5 relative (see adsb_approaches.hpp): 600 m * 1e-5.
    CHECK(*ap.glide_deg == Approx(3.0).margin(1e-6));
    CHECK(*ap.fitted_offset_m == Approx(0.0).margin(0.01));
  }
}

TEST_CASE("injected glitches are removed and counted by rule and the approaches survive", "[adsb]") {
  nlohmann::json doc = synthetic_flight(false);
  REQUIRE(doc.size() > 150);
  doc[20]["altitude"] = 0;  doc[60]["altitude"] = 0;  doc[61]["altitude"] = 0;        // no_height
  doc[30]["latitude"] = doc[30]["latitude"].get<double>() + 0.05;                  // 5.6 km in 5 s
  doc[90]["longitude"] = doc[90]["longitude"].get<double>() - 0.05;                // 3.7 km in 5 s
  doc[40]["altitude"] = doc[40]["altitude"].get<double>() + 3000;                  // 3000 ft in 5 s
  doc[100]["altitude"] = doc[100]["altitude"].get<double>() - 1500;
  doc[50]["latitude"] = doc[49]["latitude"]; doc[50]["longitude"] = doc[49]["longitude"];  // stale
  CleanTrack c;
  const auto a = approaches(doc, &c);
  CHECK(c.removed.at("no_height") == 3);
  CHECK(c.removed.at("position_jump") == 2);
  CHECK(c.removed.at("altitude_jump") == 2);
  CHECK(c.removed.at("position_stale") == 1);
  CHECK(c.removed_total() == 8);
  CHECK(c.kept.size() == doc.size() - 8);
  REQUIRE(a.size() == 2);
  for (const auto& ap : a) {
    CHECK(*ap.glide_deg == Approx(3.0).margin(1e-6));
    CHECK(ap.lateral_rms_m < 1e-3);
  }
}

TEST_CASE("a glitch at the anchor is reported, not silently propagated", "[adsb]") {
  nlohmann::json doc = synthetic_flight(false);
  doc[0]["latitude"] = doc[0]["latitude"].get<double>() + 1.0;  // first record 111 km off
  const auto rec = parse_adsb_records(doc.dump(), "synthetic");
  CHECK_THROWS_WITH(remove_glitches(rec, GlitchOptions{}, "synthetic"), Catch::Contains("record 0 is probably the glitch"));
}

TEST_CASE("the int8-corrupted track field changes nothing", "[adsb]") {
  const auto a = approaches(synthetic_flight(false)), b = approaches(synthetic_flight(true));
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].first == b[i].first);
    CHECK(a[i].last == b[i].last);
    CHECK(*a[i].glide_deg == *b[i].glide_deg);
  }
}

TEST_CASE("bad records: errors name the record index and the field", "[adsb][input]") {
  nlohmann::json doc = synthetic_flight(false);
  doc[5].erase("latitude");
  CHECK_THAT(error_of(doc.dump()), Catch::Contains("record 5") && Catch::Contains("'latitude' is missing"));
  doc = synthetic_flight(false);
  doc[2]["altitude"] = "high";
  CHECK_THAT(error_of(doc.dump()), Catch::Contains("record 2") && Catch::Contains("'altitude' is not a number"));
  doc = synthetic_flight(false);
  doc[7]["timestamp"] = nullptr;
  CHECK_THAT(error_of(doc.dump()), Catch::Contains("record 7") && Catch::Contains("'timestamp'"));
  doc = synthetic_flight(false);
  doc[9]["timestamp"] = doc[8]["timestamp"];
  CHECK_THAT(error_of(doc.dump()), Catch::Contains("record 9") && Catch::Contains("time order"));
  doc = synthetic_flight(false);
  doc[3]["geoaltitude"] = "x";
  CHECK_THAT(error_of(doc.dump()), Catch::Contains("record 3") && Catch::Contains("geoaltitude"));
  CHECK_THAT(error_of("{\"a\": 1}"), Catch::Contains("array"));
  CHECK_THAT(error_of("[{\"timestamp\": 1,"), Catch::Contains("f.json") && Catch::Contains("not valid JSON"));
}

TEST_CASE("gzip and plain files read the same and the export replays", "[adsb]") {
  const fs::path d = fs::temp_directory_path() / "rnav_test_adsb";
  fs::create_directories(d);
  const std::string text = synthetic_flight(false).dump();
  std::ofstream(d / "f.json") << text;
  gzFile g = gzopen((d / "f.json.gz").c_str(), "wb");
  REQUIRE(g != nullptr);
  REQUIRE(gzwrite(g, text.data(), static_cast<unsigned>(text.size())) == static_cast<int>(text.size()));
  gzclose(g);
  CHECK(read_maybe_gzip((d / "f.json.gz").string()) == text);
  CHECK(read_maybe_gzip((d / "f.json").string()) == text);
  CHECK_THROWS_AS(read_adsb_file((d / "absent.json").string()), ConfigError);

  const auto kept = remove_glitches(read_adsb_file((d / "f.json.gz").string()), {}, "f").kept;
  const auto a = find_approaches(kept, kRunway);
  REQUIRE(a.size() == 2);
  ReplayExportOptions e;
  e.lead_s = 60;
  e.end_x_m = 3000;
  const std::string csv = (d / "a.csv").string();
  fs::remove(d / "a.units.json");
  const std::size_t rows = write_replay_csv(csv, kept, a[1], kRunway, e);
  CHECK(rnav_test::csv_units_problem(csv) == "");  // a.units.json beside it, keys = the header's columns
  // 60 s of lead = 12 samples before the start (x = 11625 m); then x = 11625 - 375 k >= 3000:
  // 24 samples.
  CHECK(rows == 12 + 24);
  const LocalLevelFrame L(kRunway.threshold, std::fmod(kRunway.heading_deg + 180.0, 360.0));
  const ReplayTrajectory r(csv, L, 30, 15);
  CHECK(r.duration_s() == Approx(35 * 5.0));
  // The last sample: x = 3000 m on the glide path, 15 + 3000 tan 3 deg high (offset 0).
  CHECK(r.sample_p_TA_L(rows - 1).x() == Approx(3000).margin(0.01));
  CHECK(r.sample_p_TA_L(rows - 1).y() == Approx(15 + 3000 * std::tan(3 * kDegToRad)).margin(0.02));
}

TEST_CASE("real Vienna inspection flight: 17 approaches, most within 60 m RMS of one line",
          "[adsb][real]") {
  const std::string f = std::string(RNAV_DATA_DIR) + "/adsb/vienna.json.gz";
  REQUIRE(fs::exists(f));  // the recordings are part of the repository (test/data)
  const auto rec = read_adsb_file(f);
  CHECK(rec.size() == 2738);  // the data README's count
  const auto c = remove_glitches(rec, GlitchOptions{}, f);
  CHECK(c.removed.at("no_height") == 1);  // the README: one altitude == 0 point
  const auto a = find_approaches(c.kept, kRunway);
  CHECK(a.size() == 17);  // the README: 17 repeated approaches on 295.9 deg
  int straight = 0;
  for (const auto& ap : a) {
    if (ap.lateral_rms_m < 60) ++straight;
    REQUIRE(ap.glide_deg.has_value());
    CHECK(*ap.glide_deg > 2.5);  // the README's fitted 2.8-3.6 deg
    CHECK(*ap.glide_deg < 3.8);
  }
  CHECK(straight >= 10);
}
