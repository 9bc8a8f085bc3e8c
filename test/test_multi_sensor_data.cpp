// The multi-sensor, multi-target CSV format: round trip, every kind of bad input named by
// file:line, and the Autoferry import (counts against the data set's README, detections on
// the boats' GNSS truth, malformed JSON named by record).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include "common/io/config.hpp"
#include "common/io/csv_table.hpp"
#include "test/csv_units.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

const double kNaN = std::nan("");

/// A fresh, empty temporary folder private to this process.
fs::path temp_dir(const std::string& tag) {
  const fs::path d = fs::temp_directory_path() / ("rnav_msd_" + tag + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// NaN equals NaN; otherwise |a - b| <= tol.
bool near(double a, double b, double tol) { return (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= tol; }

MultiSensorData sample_data() {
  MultiSensorData d;
  d.observer = {{100.0, {63.4, 10.4, 40.0}}, {100.5, {63.40001, 10.40002, 40.1}}, {101.0, {63.40002, 10.40004, 40.2}}};
  const double r = kDegToRad;
  d.detections = {
      {100.0, "radar", 250.125, 30.5 * r, kNaN},    {100.1, "eo", kNaN, -170.25 * r, kNaN},  // interleaved
      {100.0, "radar", 12.5, 180.0 * r, 2.5 * r},   {100.1, "eo", kNaN, 179.999 * r, kNaN},
      {100.2, "lidar", kNaN, kNaN, kNaN},           {100.7, "radar", kNaN, kNaN, kNaN},      // empty scans
      {100.7, "lidar", 0.0, 0.0, -1.0 * r},         {100.9, "ir_2", kNaN, 45.0 * r, kNaN}};
  d.truth["1"] = {{100.0, {63.401, 10.401, 39.9}}, {100.04, {63.40101, 10.40101, 39.9}}};
  d.truth["Gunnerus_2"] = {{99.8, {63.402, 10.402, kNaN}}, {100.0, {63.40201, 10.40202, kNaN}}};
  return d;
}

void check_equal(const MultiSensorData& a, const MultiSensorData& b) {
  REQUIRE(a.observer.size() == b.observer.size());
  for (std::size_t i = 0; i < a.observer.size(); ++i) {
    CHECK(near(a.observer[i].t_s, b.observer[i].t_s, 1e-6));
    CHECK(near(a.observer[i].g.lat_deg, b.observer[i].g.lat_deg, 1e-10));
    CHECK(near(a.observer[i].g.lon_deg, b.observer[i].g.lon_deg, 1e-10));
    CHECK(near(a.observer[i].g.h_m, b.observer[i].g.h_m, 1e-4));
    const double ha = a.observer_heading_deg.empty() ? kNaN : a.observer_heading_deg[i];
    CHECK(near(ha, b.observer_heading_deg.at(i), 1e-6));
  }
  REQUIRE(a.detections.size() == b.detections.size());
  for (std::size_t i = 0; i < a.detections.size(); ++i) {
    const auto &x = a.detections[i], &y = b.detections[i];
    INFO("detection " << i);
    CHECK(near(x.t_s, y.t_s, 1e-6));
    CHECK(x.sensor == y.sensor);
    CHECK(near(x.range_m, y.range_m, 1e-3));
    CHECK(near(wrap_pi(x.bearing_rad), y.bearing_rad, 1e-6 * kDegToRad));
    CHECK(near(x.elevation_rad, y.elevation_rad, 1e-6 * kDegToRad));
    CHECK(x.empty_scan() == y.empty_scan());
  }
  REQUIRE(a.truth.size() == b.truth.size());
  for (const auto& [name, v] : a.truth) {
    REQUIRE(b.truth.count(name) == 1);
    const auto& w = b.truth.at(name);
    REQUIRE(v.size() == w.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      CHECK(near(v[i].t_s, w[i].t_s, 1e-6));
      CHECK(near(v[i].g.lat_deg, w[i].g.lat_deg, 1e-10));
      CHECK(near(v[i].g.lon_deg, w[i].g.lon_deg, 1e-10));
      CHECK(near(v[i].g.h_m, w[i].g.h_m, 1e-4));
    }
  }
}

/// The message of the ConfigError that reading `dir` throws ("" if none).
std::string read_error(const fs::path& dir) {
  try {
    MultiSensorData::read_folder(dir.string());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// Run a shell command; its exit code, stderr into `err`.
int run(const std::string& cmd, const fs::path& tmp, std::string& err) {
  const fs::path ef = tmp / "stderr.txt";
  const int st = std::system((cmd + " 2>" + ef.string()).c_str());
  std::ifstream in(ef);
  std::stringstream ss;
  ss << in.rdbuf();
  err = ss.str();
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

const std::string kImport = std::string(RNAV_BINARY_DIR) + "/bin/rnav_import_autoferry";

/// Horizontal position (north, east) [m] of a time series in F at t, linearly interpolated;
/// false outside its span or across a gap longer than max_gap_s [s].
bool interp(const std::vector<GeoSample>& v, const LocalLevelFrame& F, double t, double max_gap_s,
            Eigen::Vector2d& ne) {
  const auto it = std::lower_bound(v.begin(), v.end(), t, [](const GeoSample& s, double x) { return s.t_s < x; });
  if (it == v.end()) return false;
  const auto q = F.from_geodetic(it->g);
  if (it->t_s == t) {
    ne = {q.x(), q.z()};
    return true;
  }
  if (it == v.begin() || it->t_s - (it - 1)->t_s > max_gap_s) return false;
  const auto p = F.from_geodetic((it - 1)->g);
  const double a = (t - (it - 1)->t_s) / (it->t_s - (it - 1)->t_s);
  ne = Eigen::Vector2d(p.x(), p.z()) * (1 - a) + Eigen::Vector2d(q.x(), q.z()) * a;
  return true;
}

}  // namespace

TEST_CASE("multi-sensor data: write and read back", "[multisensor][io]") {
  const fs::path dir = temp_dir("rt");
  MultiSensorData d = sample_data();
  SECTION("no heading column") {
    d.write_folder(dir.string());
    std::ifstream in(dir / "observer.csv");
    std::string header;
    std::getline(in, header);
    CHECK(header == "t_s,lat_deg,lon_deg,h_m");
    // observer, detections, truth: each with its units.json (keys = the header, optional
    // columns only where written), which the reader passes over
    int n_csv = 0;
    CHECK(rnav_test::csv_folder_units_problems(dir, &n_csv) == "");
    CHECK(n_csv == 3);
    const auto r = MultiSensorData::read_folder(dir.string());
    check_equal(d, r);
    CHECK(r.sensors() == std::vector<std::string>{"eo", "ir_2", "lidar", "radar"});
    CHECK(std::isnan(r.truth.at("Gunnerus_2")[0].g.h_m));
  }
  SECTION("heading column, some cells empty") {
    d.observer_heading_deg = {0.0, kNaN, 359.5};
    d.write_folder(dir.string());
    CHECK(rnav_test::csv_folder_units_problems(dir) == "");
    std::ifstream u(dir / "observer.units.json");
    std::stringstream units;
    units << u.rdbuf();
    CHECK(units.str().find("\"heading_deg\": {\"unit\": \"deg\"") != std::string::npos);
    check_equal(d, MultiSensorData::read_folder(dir.string()));
  }
  SECTION("without truth: no truth.csv (a stale one removed), empty map") {
    d.write_folder(dir.string());
    REQUIRE(fs::exists(dir / "truth.units.json"));
    d.truth.clear();
    d.write_folder(dir.string());
    CHECK(!fs::exists(dir / "truth.csv"));
    CHECK(!fs::exists(dir / "truth.units.json"));
    CHECK(rnav_test::csv_folder_units_problems(dir) == "");
    CHECK(MultiSensorData::read_folder(dir.string()).truth.empty());
  }
  SECTION("hull sizes: targets.csv written and read back, unknown kept unknown, a stale one removed") {
    d.hull["Gunnerus_2"] = {31.25, 9.6};
    d.hull["boat_b"] = {kNaN, 4.5};
    d.write_folder(dir.string());
    int n_csv = 0;
    CHECK(rnav_test::csv_folder_units_problems(dir, &n_csv) == "");
    CHECK(n_csv == 4);
    const auto r = MultiSensorData::read_folder(dir.string());
    REQUIRE(r.hull.size() == 2);
    CHECK(r.hull.at("Gunnerus_2").length_m == 31.25);
    CHECK(r.hull.at("Gunnerus_2").beam_m == 9.6);
    CHECK(std::isnan(r.hull.at("boat_b").length_m));
    CHECK(r.hull.at("boat_b").beam_m == 4.5);
    d.hull["Gunnerus_2"].beam_m = -1;  // not a size
    CHECK_THROWS_WITH(d.write_folder(dir.string()), Catch::Contains("Gunnerus_2") && Catch::Contains("-1"));
    d.hull.clear();
    d.write_folder(dir.string());
    CHECK(!fs::exists(dir / "targets.csv"));
    CHECK(!fs::exists(dir / "targets.units.json"));
    CHECK(MultiSensorData::read_folder(dir.string()).hull.empty());
  }
  SECTION("a link in place of a file is replaced, never written through; a failed write names the file") {
    // (A full disk: test_integration's 64 kB tmpfs; here the partial file cannot be created.)
    std::ofstream(dir / "victim.txt") << "precious";
    fs::create_symlink(dir / "victim.txt", dir / "detections.csv");
    d.write_folder(dir.string());
    CHECK(fs::is_regular_file(fs::symlink_status(dir / "detections.csv")));
    std::ifstream v(dir / "victim.txt");
    std::string text;
    v >> text;
    CHECK(text == "precious");
    fs::create_directories(dir / ".truth.csv.partial" / "in_the_way");
    CHECK_THROWS_WITH(d.write_folder(dir.string()), Catch::Contains(".truth.csv.partial"));
  }
  fs::remove_all(dir);
}

/// A folder of sample data whose files the cases below spoil one at a time; each read error must
/// name the file, the line and (where given) the column.
const std::string kDetectionsHeader = "t_s,sensor,range_m,bearing_deg\n";

struct SpoiltFolder {
  const fs::path dir = temp_dir("bad");
  SpoiltFolder() {
    sample_data().write_folder(dir.string());
    REQUIRE(read_error(dir).empty());
  }
  ~SpoiltFolder() { fs::remove_all(dir); }
  SpoiltFolder(const SpoiltFolder&) = delete;
  SpoiltFolder& operator=(const SpoiltFolder&) = delete;
  /// detections.csv with the standard header and these rows
  void det(const std::string& rows) const {
    std::ofstream(dir / "detections.csv") << kDetectionsHeader << rows;
  }
  /// the folder's read error names `where` and, unless empty, the column `col`
  void expect(const std::string& where, const std::string& col) const {
    const std::string e = read_error(dir);
    INFO(e);
    CHECK(e.find(where) != std::string::npos);
    if (!col.empty()) CHECK(e.find("column '" + col + "'") != std::string::npos);
    CHECK(!e.empty());
  }
  /// `file` gets `content`; then expect(where, col)
  void expect_in(const std::string& file, const std::string& content, const std::string& where,
                 const std::string& col) const {
    std::ofstream(dir / file) << content;
    expect(where, col);
  }
};

TEST_CASE("multi-sensor data: bad detections name file and line and column", "[multisensor][input]") {
  const SpoiltFolder f;
  const fs::path& dir = f.dir;
  SECTION("a header separated by ';' is named as such") {
    std::ofstream(dir / "detections.csv") << "t_s;sensor;range_m;bearing_deg\n1;radar;10;20\n";
    f.expect("detections.csv:1: the header is separated by ';'", "");
  }
  SECTION("a file cut inside its last number (no final newline) is refused, not read as a shorter number") {
    f.det("1,radar,10,20\n2,radar,10,2");  // "2" may be the start of "20.5"
    f.expect("detections.csv: the last line has no newline: the file may have been cut", "");
  }
  SECTION("bearings in milliradians (beyond two turns read as degrees) are named as such") {
    f.det("1,radar,10,20\n2,radar,10,5000\n");
    f.expect("detections.csv:3", "");
    f.expect("5000 is outside [-360, 360] (milliradians in a degree column?)", "bearing_deg");
  }
  SECTION("a reference track in radians (lat_deg, lon_deg) is named as such") {
    std::ofstream(dir / "truth.csv") << "t_s,target,lat_deg,lon_deg\n0,1,1.1,0.18\n1,1,1.1,0.18\n";
    f.expect("truth.csv lat_deg and truth.csv lon_deg look like radians", "");
  }
  SECTION("a byte-order mark before the header is named, not read as a column 't_s' missing") {
    std::ofstream(dir / "detections.csv") << "\xEF\xBB\xBF" << kDetectionsHeader << "1,radar,10,20\n";
    f.expect("detections.csv:1: starts with a byte-order mark", "");
  }
  SECTION("a raw Autoferry folder is answered with the command that imports it") {
    const fs::path raw = temp_dir("scenario9");
    std::ofstream(raw / "scenario9_detections.json") << "[]";
    std::ofstream(raw / "scenario9_groundTruth.json") << "[]";
    const std::string e = read_error(raw);
    INFO(e);
    CHECK(e.find("a raw Autoferry folder") != std::string::npos);
    CHECK(e.find("rnav_import_autoferry " + raw.string() + " --out out/" + raw.filename().string()) != std::string::npos);
  }
  SECTION("non-numeric cell") {
    f.det("1,radar,10,20\n2,radar,abc,20\n");
    f.expect("detections.csv:3", "range_m");
  }
  SECTION("a CSV beyond the input limit is refused up front, naming its size and the limit") {
    const std::uint64_t before = max_csv_bytes();
    set_max_csv_bytes(20);  // [bytes]: less than detections.csv holds
    const std::string e = read_error(dir);
    set_max_csv_bytes(before);
    INFO(e);
    CHECK(e.find("MB is more than the input limit of 2e-05 MB (rnav_diagnose --max-input-mb M raises it)") != std::string::npos);
    CHECK(read_error(dir).empty());  // the default limit reads it
    CHECK_THROWS_AS(set_max_csv_bytes(0), ConfigError);
  }
  SECTION("a FIFO given as a CSV is refused by its type, not waited on") {
    fs::remove(dir / "detections.csv");
    REQUIRE(::mkfifo((dir / "detections.csv").c_str(), 0600) == 0);
    f.expect("detections.csv: is a FIFO (named pipe), not a regular file", "");
  }
  SECTION("a hexadecimal float is not a decimal number (strtod read 0x1.0p+15 as 32768)") {
    f.det("1,radar,10,20\n2,radar,0x1.0p+15,20\n");
    f.expect("detections.csv:3", "range_m");
    CHECK(read_error(dir).find("not a decimal number") != std::string::npos);
  }
  SECTION("a number beyond the double range is named as such") {
    f.det("1,radar,10,20\n2,radar,1e400,20\n");
    f.expect("detections.csv:3", "range_m");
    CHECK(read_error(dir).find("overflows the double range") != std::string::npos);
  }
  SECTION("bad sensor name") {
    f.det("1,radar,10,20\n2,Radar,10,20\n");
    f.expect("detections.csv:3", "sensor");
  }
  SECTION("empty sensor name") {
    f.det("1,radar,10,20\n2,,10,20\n");
    f.expect("detections.csv:3", "sensor");
  }
  SECTION("negative range") {
    f.det("1,radar,10,20\n2,radar,-1,20\n");
    f.expect("detections.csv:3", "range_m");
  }
  SECTION("bearing 400") {
    f.det("1,radar,10,20\n2,radar,10,400\n");
    f.expect("detections.csv:3", "bearing_deg");
  }
  SECTION("range without bearing") {
    f.det("1,radar,10,20\n2,radar,10,\n");
    f.expect("detections.csv:3", "bearing_deg");
  }
  SECTION("elevation out of range") {
    f.expect_in("detections.csv", "t_s,sensor,range_m,bearing_deg,elevation_deg\n1,radar,10,20,\n2,radar,10,20,91\n", "detections.csv:3", "elevation_deg");
  }
  SECTION("time going backwards within a sensor; two sensors interleaving is fine") {
    f.det("100.1,radar,10,20\n100.05,eo,,20\n100.1,radar,12,21\n100.2,radar,10,20\n100.15,eo,,20\n");
    CHECK(read_error(dir).empty());
    f.det("1,radar,10,20\n0.5,eo,,20\n2,radar,10,20\n1.9,radar,10,20\n");
    f.expect("detections.csv:5", "t_s");
  }
  SECTION("an empty scan beside a detection at one time") {
    f.det("1,radar,10,20\n1,radar,,\n");
    f.expect("detections.csv:3", "bearing_deg");
  }
  SECTION("no detections at all") {
    f.det("1,radar,,\n");
    f.expect("detections.csv", "");
    f.det("");
    f.expect("detections.csv", "");
  }
  SECTION("missing column") {
    f.expect_in("detections.csv", "t_s,sensor,bearing_deg\n1,radar,20\n", "detections.csv:1", "range_m");
  }
}

TEST_CASE("multi-sensor data: bad observer and truth name file and line and column", "[multisensor][input]") {
  const SpoiltFolder f;
  const fs::path& dir = f.dir;
  SECTION("observer: time order, latitude, heading, fewer than 2 rows") {
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n1,63,10,0\n", "observer.csv:3", "t_s");
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n2,91,10,0\n", "observer.csv:3", "lat_deg");
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n2,63,-181,0\n", "observer.csv:3", "lon_deg");
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m,heading_deg\n1,63,10,0,\n2,63,10,0,360\n", "observer.csv:3", "heading_deg");
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n", "observer.csv", "");
  }
  SECTION("the shared plausibility layer: height, swapped coordinates, far truth, absurd time") {
    // Each passes the per-cell format checks above and is caught by validate(), naming the sample.
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n2,63,10,1e9\n", "observer sample 1: height", "");
    f.expect_in("observer.csv", "t_s,lat_deg,lon_deg,h_m\n1,63,10,0\n2,10,63,0\n", "observer sample 1", "");
    CHECK(read_error(dir).find("latitude and longitude swapped") != std::string::npos);
    sample_data().write_folder(dir.string());
    f.expect_in("truth.csv", "t_s,target,lat_deg,lon_deg\n1,1,63,10\n2,1,10,63\n", "truth of target 1 sample 1", "");
    fs::remove(dir / "truth.csv");
    f.det("1,radar,10,20\n1e300,radar,10,20\n");
    f.expect("detection 1 (sensor radar): time 1e+300 s", "");
  }
  SECTION("truth: time order per target, target name; missing truth.csv is fine") {
    std::ofstream(dir / "truth.csv") << "t_s,target,lat_deg,lon_deg\n100,1,63,10\n100.5,2,63,10\n101,1,63,10\n";
    CHECK(read_error(dir).empty());
    f.expect_in("truth.csv", "t_s,target,lat_deg,lon_deg\n1,1,63,10\n0.5,2,63,10\n0.9,1,63,10\n", "truth.csv:4", "t_s");
    f.expect_in("truth.csv", "t_s,target,lat_deg,lon_deg\n1,1,63,10\n2,boat-1,63,10\n", "truth.csv:3", "target");
    f.expect_in("truth.csv", "t_s,target,lat_deg,lon_deg,h_m\n1,1,63,10,\n2,1,63,10,x\n", "truth.csv:3", "h_m");
    fs::remove(dir / "truth.csv");
    CHECK(read_error(dir).empty());
    CHECK(MultiSensorData::read_folder(dir.string()).truth.empty());
  }
  SECTION("targets.csv: hull sizes, 0 and empty unknown; bad name, value or a second row named") {
    std::ofstream(dir / "targets.csv") << "target,length_m,beam_m\nA,120.5,18\nB,0,\n";
    REQUIRE(read_error(dir).empty());
    const MultiSensorData d = MultiSensorData::read_folder(dir.string());
    CHECK(d.hull.at("A").length_m == 120.5);
    CHECK(d.hull.at("A").beam_m == 18);
    CHECK(std::isnan(d.hull.at("B").length_m));
    CHECK(std::isnan(d.hull.at("B").beam_m));
    f.expect_in("targets.csv", "target,length_m,beam_m\nA,-3,18\n", "targets.csv:2", "length_m");
    f.expect_in("targets.csv", "target,length_m,beam_m\nA,30,5000\n", "targets.csv:2", "beam_m");
    f.expect_in("targets.csv", "target,length_m,beam_m\nA,30,5\nA,31,5\n", "targets.csv:3", "target");
    f.expect_in("targets.csv", "target,length_m,beam_m\nboat-1,30,5\n", "targets.csv:2", "target");
    f.expect_in("targets.csv", "target,length_m\nA,30\n", "targets.csv", "beam_m");
    fs::remove(dir / "targets.csv");
  }
}

TEST_CASE("Autoferry import: counts of the README, radar and lidar on the GNSS truth",
          "[multisensor][autoferry][real]") {
  const std::string data = std::string(RNAV_DATA_DIR) + "/autoferry";
  REQUIRE(fs::exists(data));  // the recordings are part of the repository (test/data)
  struct Count {
    std::size_t scans, detections;
  };
  // From the README's "Scenarios" table: EO, IR frames/bearings; radar, lidar scans/points;
  // truth unique samples of targets 1 / 2.
  const std::map<int, std::map<std::string, Count>> expected = {
      {2, {{"eo", {591, 1944}}, {"ir", {1012, 1446}}, {"radar", {70, 437}}, {"lidar", {234, 412}}}},
      {22, {{"eo", {423, 5652}}, {"ir", {724, 2507}}, {"radar", {50, 263}}, {"lidar", {168, 170}}}}};
  const std::map<int, std::array<std::size_t, 2>> truth_n = {{2, {1554, 591}}, {22, {854, 423}}};
  const fs::path tmp = temp_dir("af");
  for (const auto& [sc, exp] : expected) {
    const fs::path out = tmp / ("sc" + std::to_string(sc));
    std::string err;
    REQUIRE(run(kImport + " " + data + "/scenario" + std::to_string(sc) + " --out " + out.string(), tmp, err) == 0);
    CHECK(err.find("sensor radar: " + std::to_string(exp.at("radar").scans) + " scans") != std::string::npos);
    int n_csv = 0;
    CHECK(rnav_test::csv_folder_units_problems(out, &n_csv) == "");
    CHECK(n_csv == 3);
    const auto d = MultiSensorData::read_folder(out.string());
    CHECK(d.sensors() == std::vector<std::string>{"eo", "ir", "lidar", "radar"});
    for (const auto& [s, c] : exp) {
      std::set<double> scans;
      std::size_t n = 0;
      for (const auto& x : d.detections)
        if (x.sensor == s) {
          scans.insert(x.t_s);
          n += x.empty_scan() ? 0 : 1;
        }
      INFO("scenario " << sc << " sensor " << s);
      CHECK(scans.size() == c.scans);
      CHECK(n == c.detections);
    }
    REQUIRE(d.truth.size() == 2);
    CHECK(d.truth.at("1").size() == truth_n.at(sc)[0]);
    CHECK(d.truth.at("2").size() == truth_n.at(sc)[1]);

    // Physics: per radar/lidar scan and target, the detection nearest to the interpolated truth.
    const LocalLevelFrame F(d.observer.front().g, 0.0);  // x north, y up, z east
    for (const std::string s : {"radar", "lidar"}) {
      std::map<std::string, std::map<double, double>> nearest;  // target -> scan time -> distance [m]
      for (const auto& x : d.detections) {
        if (x.sensor != s || x.empty_scan()) continue;
        Eigen::Vector2d own, tgt;
        REQUIRE(interp(d.observer, F, x.t_s, 1.0, own));
        const Eigen::Vector2d p = own + x.range_m * Eigen::Vector2d(std::cos(x.bearing_rad), std::sin(x.bearing_rad));
        for (const auto& [name, v] : d.truth) {
          if (!interp(v, F, x.t_s, 1.0, tgt)) continue;
          auto [it, fresh] = nearest[name].emplace(x.t_s, 1e9);
          it->second = std::min(it->second, (p - tgt).norm());
        }
      }
      std::size_t within50 = 0, within15 = 0;
      for (const auto& [name, m] : nearest) {
        std::size_t a = 0, b = 0;
        for (const auto& [t, dist] : m) {
          a += dist <= 50;
          b += dist <= 15;
        }
        std::cout << "scenario " << sc << " " << s << " target " << name << ": " << b << " of " << a
                  << " scans with a detection within 50 m have one within 15 m ("
                  << (a ? 100.0 * b / a : 0.0) << " %)\n";
        within50 += a;
        within15 += b;
      }
      INFO("scenario " << sc << " " << s);
      REQUIRE(within50 > 10);
      CHECK(static_cast<double>(within15) >= 0.8 * static_cast<double>(within50));
    }
  }
  fs::remove_all(tmp);
}

TEST_CASE("Autoferry import: malformed JSON is named by file and record", "[multisensor][autoferry][input]") {
  const fs::path tmp = temp_dir("json");
  const fs::path sc = tmp / "scenarioX";
  fs::create_directories(sc);
  const std::string gt_ok = R"([{"targetID":1,"position":[1,2,0],"time":10.0},{"targetID":2,"position":[3,4,0],"time":10.0}])";
  auto write = [&](const std::string& rec1, const std::string& gt1) {
    std::ofstream(sc / "scenarioX_detections.json")
        << "[{\"sensorID\":2,\"time\":10.0,\"ownshipPosition\":[0,0],\"measurement\":[[1,2],[3,4]],\"measurements\":[]},"
        << rec1 << "]";
    std::ofstream(sc / "scenarioX_groundTruth.json") << "[" << gt_ok << "," << gt1 << "]";
  };
  const std::string cmd = kImport + " " + sc.string() + " --out " + (tmp / "out").string();
  std::string err;
  const std::string eo_ok = R"({"sensorID":4,"time":10.1,"ownshipPosition":[0,0],"measurement":0.5})";
  SECTION("well formed: imports") {
    write(eo_ok, gt_ok);
    CHECK(run(cmd, tmp, err) == 0);
    INFO(err);
    CHECK(err.find("sensor radar: 1 scans, 2 detections") != std::string::npos);
  }
  // The import of (rec1, gt1) fails and its message holds every one of `needles`.
  auto fails_with = [&](const std::string& rec1, const std::string& gt1, const std::vector<std::string>& needles) {
    write(rec1, gt1);
    CHECK(run(cmd, tmp, err) != 0);
    INFO(err);
    for (const auto& n : needles) CHECK(err.find(n) != std::string::npos);
  };
  SECTION("short ownshipPosition") {
    fails_with(R"({"sensorID":4,"time":10.1,"ownshipPosition":[0],"measurement":0.5})", gt_ok,
               {"scenarioX_detections.json record 1", "ownshipPosition"});
  }
  SECTION("the azimuth-only mode checks the same (it indexed a short ownshipPosition out of bounds)") {
    const std::string az = kImport + " " + sc.string() + " --sensor eo --target 1 --out " + (tmp / "out_az").string();
    write(R"({"sensorID":4,"time":10.1,"ownshipPosition":[0],"measurement":0.5})", gt_ok);
    CHECK(run(az, tmp, err) != 0);
    CHECK(err.find("record 1: ownshipPosition has 1 numbers, not 2") != std::string::npos);
    write(eo_ok, R"([{"targetID":1,"position":[1],"time":10.0}])");
    CHECK(run(az, tmp, err) != 0);
    CHECK(err.find("scenarioX_groundTruth.json element 1: position has 1 numbers") != std::string::npos);
    write(R"({"sensorID":4,"time":"soon","ownshipPosition":[0,0],"measurement":0.5})", gt_ok);
    CHECK(run(az, tmp, err) != 0);
    CHECK(err.find("record 1: time is not a number") != std::string::npos);
  }
  SECTION("positions that cannot belong to the scene: named by the plausibility layer, both modes") {
    // 3000 km north of Piren: beyond the 2000 km scene bound (a unit or frame mix-up).
    fails_with(R"({"sensorID":4,"time":10.1,"ownshipPosition":[3e6,0],"measurement":0.5})", gt_ok,
               {"scenarioX_detections.json (imported): observer sample", "km from the observer's first position"});
    fails_with(eo_ok, R"([{"targetID":2,"position":[0,3e6,0],"time":10.1}])",
               {"truth of target 2 sample 1", "km from"});
    fails_with(eo_ok, R"([{"targetID":2,"position":[0,0,-1e9],"time":10.1}])", {"truth of target 2", "height"});
    const std::string az = kImport + " " + sc.string() + " --sensor eo --target 1 --out " + (tmp / "out_az").string();
    write(R"({"sensorID":4,"time":10.1,"ownshipPosition":[3e6,0],"measurement":0.5})", gt_ok);
    CHECK(run(az, tmp, err) != 0);
    // The camera's only frame: no first position to be far from, but 3000 km along the local
    // level frame's tangent plane is also 670 km up.
    CHECK(err.find("(imported eo): observer sample 0: height") != std::string::npos);
    write(R"({"sensorID":4,"time":1e300,"ownshipPosition":[0,0],"measurement":0.5})", gt_ok);
    CHECK(run(az, tmp, err) != 0);
    CHECK(err.find("record 1: time 1e+300 is outside [0, 4102444800] s") != std::string::npos);
  }
  SECTION("a time beyond Unix seconds is named on its own record (it was blamed on the next one), ms named as such") {
    write(R"({"sensorID":2,"time":1e30,"ownshipPosition":[0,0],"measurement":[]},)"
          R"({"sensorID":2,"time":12.0,"ownshipPosition":[0,0],"measurement":[]})", gt_ok + "," + gt_ok);
    CHECK(run(cmd, tmp, err) != 0);
    INFO(err);
    CHECK(err.find("scenarioX_detections.json record 1: time 1e+30 is outside [0, 4102444800] s") != std::string::npos);
    fails_with(R"({"sensorID":4,"time":1620115864722.0,"ownshipPosition":[0,0],"measurement":0.5})", gt_ok,
               {"record 1: time 1.62012e+12 is outside", "milliseconds?"});
  }
  SECTION("a failed import leaves no output folder behind") {
    write(R"({"sensorID":4,"time":1e30,"ownshipPosition":[0,0],"measurement":0.5})", gt_ok);
    fs::remove_all(tmp / "out");
    CHECK(run(cmd, tmp, err) != 0);
    CHECK(!fs::exists(tmp / "out"));
    write(eo_ok, gt_ok);
    CHECK(run(cmd, tmp, err) == 0);  // the same folder then imports
    CHECK(fs::exists(tmp / "out" / "detections.csv"));
  }
  SECTION("ragged radar rows") {
    fails_with(R"({"sensorID":2,"time":11.0,"ownshipPosition":[0,0],"measurement":[[1,2,3],[4,5]]})", gt_ok,
               {"record 1", "differ in length"});
  }
  SECTION("missing key, non-numeric value, unknown sensor") {
    fails_with(R"({"sensorID":4,"ownshipPosition":[0,0],"measurement":0.5})", gt_ok, {"record 1: missing key 'time'"});
    fails_with(R"({"sensorID":3,"time":10.1,"ownshipPosition":[0,0],"measurement":[0.5,"x"]})", gt_ok,
               {"record 1: measurement[1] is not a number"});
    fails_with(R"({"sensorID":7,"time":10.1,"ownshipPosition":[0,0],"measurement":[]})", gt_ok,
               {"record 1: unknown sensorID 7"});
  }
  SECTION("ground-truth element of a wrong shape") {
    fails_with(eo_ok, R"([{"targetID":1,"position":[1,2],"time":10.0}])",
               {"scenarioX_groundTruth.json element 1", "position"});
    fails_with(eo_ok, "{\"targetID\":1}", {"element 1: not a list"});
  }
  SECTION("--help: usage of both modes on stdout") {
    CHECK(run(kImport + " --help >" + (tmp / "usage.txt").string(), tmp, err) == 0);
    std::ifstream in(tmp / "usage.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    CHECK(ss.str().find("--out DIR") != std::string::npos);
    CHECK(ss.str().find("--sensor eo|ir --target 1|2") != std::string::npos);
  }
  fs::remove_all(tmp);
}
