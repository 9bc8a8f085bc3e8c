#include "estimators/diagnosis/multi_sensor_data.hpp"

#include "common/io/atomic_file.hpp"

#include "common/io/config.hpp"
#include "common/io/csv_table.hpp"
#include "estimators/diagnosis/gross_check.hpp"
#include "common/io/plausible.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rnav {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMaxRange_m = 1e6;

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", x);
  return b;
}

/// ConfigError "FILE:LINE: column 'COL': WHAT" for row i of t.
[[noreturn]] void fail(const CsvTable& t, std::size_t i, const std::string& col, const std::string& what) {
  throw ConfigError(t.file() + ":" + std::to_string(t.line(i)) + ": column '" + col + "': " + what);
}

/// Latitude in [-90, 90] and longitude in [-180, 360] of row i, else ConfigError.
void check_lat_lon(const CsvTable& t, std::size_t i) {
  const double lat = t.col("lat_deg")[i], lon = t.col("lon_deg")[i];
  if (lat < -90 || lat > 90) fail(t, i, "lat_deg", num(lat) + " is outside [-90, 90]");
  if (lon < -180 || lon > 360) fail(t, i, "lon_deg", num(lon) + " is outside [-180, 360]");
}

bool name_chars(const std::string& s, bool upper) {
  if (s.empty()) return false;
  for (char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || (upper && c >= 'A' && c <= 'Z')))
      return false;
  return true;
}

void read_observer(const std::string& file, MultiSensorData& d) {
  const CsvTable t = CsvTable::read_columns(
      file, {{"t_s"}, {"lat_deg"}, {"lon_deg"}, {"h_m"}, {"heading_deg", CsvKind::kNumberOrEmpty, true}});
  t.require_time_order("t_s", false);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    check_lat_lon(t, i);
    const double hdg = t.has("heading_deg") ? t.col("heading_deg")[i] : kNaN;
    if (!std::isnan(hdg) && (hdg < 0 || hdg >= 360)) fail(t, i, "heading_deg", num(hdg) + " is outside [0, 360)");
    d.observer.push_back({t.col("t_s")[i], {t.col("lat_deg")[i], t.col("lon_deg")[i], t.col("h_m")[i]}});
    d.observer_heading_deg.push_back(hdg);
  }
  if (d.observer.size() < 2)
    throw ConfigError(file + ": " + std::to_string(d.observer.size()) + " data rows, at least 2 are needed");
}

void read_detections(const std::string& file, MultiSensorData& d) {
  const CsvTable t = CsvTable::read_columns(file, {{"t_s"},
                                                   {"sensor", CsvKind::kText},
                                                   {"range_m", CsvKind::kNumberOrEmpty},
                                                   {"bearing_deg", CsvKind::kNumberOrEmpty},
                                                   {"elevation_deg", CsvKind::kNumberOrEmpty, true}});
  struct Scan {
    double t_s;
    bool empty;  // the scan's row so far is an empty-scan row
  };
  std::map<std::string, Scan> last;  // per sensor: its latest scan
  std::size_t n_det = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    Detection x;
    x.t_s = t.col("t_s")[i];
    x.sensor = t.text("sensor")[i];
    x.range_m = t.col("range_m")[i];
    const double b = t.col("bearing_deg")[i];
    const double e = t.has("elevation_deg") ? t.col("elevation_deg")[i] : kNaN;
    if (!valid_sensor_name(x.sensor)) fail(t, i, "sensor", "'" + x.sensor + "' is not a sensor name ([a-z0-9_]+)");
    if (!std::isnan(x.range_m) && (x.range_m < 0 || x.range_m > kMaxRange_m))
      fail(t, i, "range_m", num(x.range_m) + " is outside [0, 1e6]");
    // a degree column holding milliradians reaches 1000 x 2 pi = 6283: named as such
    if (!std::isnan(b) && (b < -360 || b > 360))
      fail(t, i, "bearing_deg",
           num(b) + " is outside [-360, 360]" + (std::abs(b) <= 2000 * M_PI + 1 ? " (milliradians in a degree column?)" : ""));
    if (std::isnan(b) && !std::isnan(x.range_m)) fail(t, i, "bearing_deg", "empty, but range_m is given");
    if (!std::isnan(e) && (e < -90 || e > 90)) fail(t, i, "elevation_deg", num(e) + " is outside [-90, 90]");
    if (std::isnan(b) && !std::isnan(e)) fail(t, i, "elevation_deg", "given on an empty-scan row");
    x.bearing_rad = std::isnan(b) ? kNaN : wrap_pi(b * kDegToRad);
    x.elevation_rad = std::isnan(e) ? kNaN : e * kDegToRad;
    const bool empty = x.empty_scan();
    const auto it = last.find(x.sensor);
    if (it != last.end()) {
      if (x.t_s < it->second.t_s)
        fail(t, i, "t_s", "sensor '" + x.sensor + "' goes back in time (" + num(x.t_s) + " after " +
                              num(it->second.t_s) + ")");
      if (x.t_s == it->second.t_s && (empty || it->second.empty))
        fail(t, i, "bearing_deg", "sensor '" + x.sensor + "' has an empty-scan row and another row at t_s " +
                                      num(x.t_s));
    }
    last[x.sensor] = {x.t_s, empty};
    n_det += empty ? 0 : 1;
    d.detections.push_back(x);
  }
  if (n_det == 0)
    throw ConfigError(file + ": no detections at all (" + std::to_string(t.rows()) + " empty-scan rows)");
  // a sensor whose every range is 0: no range sensor (one echo at 0 m is a glitch, all of them a
  // bearing-only sensor's unknown range written as 0)
  std::map<std::string, std::pair<std::size_t, std::size_t>> zeros;  // per sensor: (rows with a range, of them 0)
  for (const Detection& x : d.detections)
    if (!std::isnan(x.range_m)) ++zeros[x.sensor].first, zeros[x.sensor].second += x.range_m == 0;
  for (const auto& [sensor, z] : zeros)
    if (z.first >= static_cast<std::size_t>(kMinUnitSamples) && z.second == z.first)
      throw ConfigError(file + ": column 'range_m' of sensor '" + sensor + "' is 0 in all its " + std::to_string(z.first) +
                        " rows: no range (a bearing-only sensor's range_m is left empty; a range sensor's is > 0)");
}

constexpr double kSameTrackShare = 0.9;  // of the shorter track's samples equal: one track under two names
void read_truth(const std::string& file, MultiSensorData& d) {
  const CsvTable t = CsvTable::read_columns(
      file, {{"t_s"}, {"target", CsvKind::kText}, {"lat_deg"}, {"lon_deg"}, {"h_m", CsvKind::kNumberOrEmpty, true}});
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const std::string& name = t.text("target")[i];
    if (!valid_target_name(name)) fail(t, i, "target", "'" + name + "' is not a target name ([A-Za-z0-9_]+)");
    check_lat_lon(t, i);
    auto& v = d.truth[name];
    const double ts = t.col("t_s")[i];
    if (!v.empty() && ts <= v.back().t_s)
      fail(t, i, "t_s", "target '" + name + "' is not in strictly increasing time (" + num(ts) + " after " +
                            num(v.back().t_s) + ")");
    v.push_back({ts, {t.col("lat_deg")[i], t.col("lon_deg")[i], t.has("h_m") ? t.col("h_m")[i] : kNaN}});
  }
  // one track under two names (a copy, or an id changed mid-file and the rows written twice): at
  // least kSameTrackShare of the shorter one's samples equal, time and position, to the other's
  for (auto a = d.truth.begin(); a != d.truth.end(); ++a)
    for (auto b = std::next(a); b != d.truth.end(); ++b) {
      const auto &u = a->second, &w = b->second;
      std::size_t i = 0, j = 0, same = 0;
      while (i < u.size() && j < w.size()) {
        if (u[i].t_s < w[j].t_s) ++i;
        else if (w[j].t_s < u[i].t_s) ++j;
        else same += u[i].g.lat_deg == w[j].g.lat_deg && u[i].g.lon_deg == w[j].g.lon_deg, ++i, ++j;
      }
      if (static_cast<double>(same) >= kSameTrackShare * static_cast<double>(std::min(u.size(), w.size())))
        throw ConfigError(file + ": targets '" + a->first + "' and '" + b->first + "' have the same track (" +
                          std::to_string(same) + " samples equal in time and position): one target under two names");
    }
}

// targets.csv: each target's hull size; 0 (AIS: not available) and empty cells are unknown.
constexpr double kMaxHullM = 1000;  // [m] no ship is longer (the largest ever built: 458 m)
void read_targets(const std::string& file, MultiSensorData& d) {
  const CsvTable t = CsvTable::read_columns(
      file, {{"target", CsvKind::kText}, {"length_m", CsvKind::kNumberOrEmpty}, {"beam_m", CsvKind::kNumberOrEmpty}});
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const std::string& name = t.text("target")[i];
    if (!valid_target_name(name)) fail(t, i, "target", "'" + name + "' is not a target name ([A-Za-z0-9_]+)");
    if (d.hull.count(name)) fail(t, i, "target", "target '" + name + "' has a second row");
    HullSize h;
    for (const char* col : {"length_m", "beam_m"}) {
      const double x = t.col(col)[i];
      if (std::isnan(x)) continue;
      if (!(x >= 0 && x <= kMaxHullM)) fail(t, i, col, "must be in [0, 1000] m (0 or empty: unknown), got " + num(x));
      (std::string(col) == "length_m" ? h.length_m : h.beam_m) = x > 0 ? x : NAN;
    }
    d.hull[name] = h;
  }
}

/// A CSV file's text, built in memory from the header of `columns`; close() writes it with
/// write_file_atomic (exclusive partial file, every byte checked, renamed into place), then its
/// description beside it (NAME.units.json), throwing naming the file on any failure.
class CheckedFile {
 public:
  CheckedFile(std::string file, std::vector<CsvColumnDoc> columns) : file_(std::move(file)), columns_(std::move(columns)) {
    f_ << csv_header(columns_);
  }
  std::ostringstream& out() { return f_; }
  void close() {
    write_file_atomic(file_, f_.str());
    write_csv_units(file_, columns_);
  }

 private:
  std::string file_;
  std::vector<CsvColumnDoc> columns_;
  std::ostringstream f_;
};

/// "%.<prec>f" of x, or "" for NaN.
std::string cell(double x, int prec) {
  if (std::isnan(x)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, x);
  return b;
}

bool any_finite(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return !std::isnan(x); });
}

}  // namespace

bool Detection::empty_scan() const { return std::isnan(bearing_rad) && std::isnan(range_m); }

bool valid_sensor_name(const std::string& s) { return name_chars(s, false); }
bool valid_target_name(const std::string& s) { return name_chars(s, true); }

std::vector<std::string> MultiSensorData::sensors() const {
  std::set<std::string> s;
  for (const auto& x : detections) s.insert(x.sensor);
  return {s.begin(), s.end()};
}

std::map<std::string, std::vector<GeoSample>> MultiSensorData::truth_on_level() const {
  auto out = truth;
  if (observer.empty()) return out;
  for (auto& [name, v] : out)
    for (auto& s : v)
      if (std::isnan(s.g.h_m)) s.g.h_m = observer.front().g.h_m;
  return out;
}

namespace {

// A raw Autoferry folder (scenarioN_detections.json and scenarioN_groundTruth.json, no CSV) is
// answered with the command that imports it, not with "observer.csv: cannot open".
void refuse_raw_autoferry(const std::string& dir) {
  namespace fs = std::filesystem;
  if (fs::exists(dir + "/observer.csv") || !fs::is_directory(dir)) return;
  std::string det, truth;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string f = e.path().filename().string();
    auto ends = [&](const std::string& tail) { return f.size() > tail.size() && f.compare(f.size() - tail.size(), tail.size(), tail) == 0; };
    if (ends("_detections.json")) det = f;
    if (ends("_groundTruth.json")) truth = f;
  }
  if (det.empty() || truth.empty()) return;
  std::string name = fs::path(dir).lexically_normal().filename().string();
  if (name.empty()) name = fs::path(dir).lexically_normal().parent_path().filename().string();
  throw ConfigError(dir + ": a raw Autoferry folder (" + det + ", " + truth + "), not the multi-sensor CSV format; "
                    "import it first: build/bin/rnav_import_autoferry " + dir + " --out out/" + name +
                    " (add --boat-names A,B to name its boats), then diagnose out/" + name);
}

// Units the range checks cannot see, by file and column (before validate's "far away", which
// would not say which column):
//   coordinates: observer.csv's and truth.csv's medians (plausible::coordinates_in_degrees), and
//                latitude and longitude swapped in one of them (coordinates_not_swapped);
//   heading:     every heading_deg within [0, 2 pi] while most of the observer's courses over
//                ground (between rows kMinCourseSpeedMps or faster, flat Earth: atan2(dE, dN))
//                lie outside that band read as degrees (bearings_look_like_radians): radians.
constexpr double kMinCourseSpeedMps = 0.5;  // [m/s] slower, the course over ground is noise
constexpr double kMetresPerDegree = 111195;  // [m] one degree of a great circle (mean radius)
constexpr double kMinHeadingTurnDeg = 10;    // [deg] a course turning by more, under a constant heading: no compass
void check_units(const MultiSensorData& d) {
  plausible::NamedPositions tru{"truth.csv lat_deg", "truth.csv lon_deg", {}};
  for (const auto& [name, v] : d.truth)
    for (const auto& s : v) tru.g.push_back(s.g);  // every target's samples together
  plausible::coordinates_in_degrees({"observer.csv lat_deg", "observer.csv lon_deg", plausible::positions(d.observer)}, tru);
  plausible::coordinates_not_swapped({"observer.csv lat_deg", "observer.csv lon_deg", plausible::positions(d.observer)}, tru);
  int n = 0, inside = 0, refs = 0, refs_outside = 0;
  std::vector<double> course;  // [rad] the observer's course over ground between moving rows
  for (std::size_t i = 0; i + 1 < d.observer.size(); ++i) {
    const double h = d.observer_heading_deg[i];
    if (!std::isnan(h)) ++n, inside += h * kDegToRad <= kRadiansAsDegreesRad;
    const Geodetic &a = d.observer[i].g, &b = d.observer[i + 1].g;
    const double dn = (b.lat_deg - a.lat_deg) * kMetresPerDegree,
                 de = (b.lon_deg - a.lon_deg) * kMetresPerDegree * std::cos(a.lat_deg * kDegToRad);
    const double dt = d.observer[i + 1].t_s - d.observer[i].t_s;
    if (!(dt > 0) || std::hypot(dn, de) / dt < kMinCourseSpeedMps) continue;
    ++refs;
    course.push_back(std::atan2(de, dn));
    refs_outside += outside_radians_band(std::fmod(course.back() + 2 * M_PI, 2 * M_PI));
  }
  // one value in every row while the ship turns: no compass behind the column (a zero or a
  // default written), before the radians check, which a constant 0 would pass
  double h_lo = INFINITY, h_hi = -INFINITY;
  for (double h : d.observer_heading_deg)
    if (!std::isnan(h)) h_lo = std::min(h_lo, h), h_hi = std::max(h_hi, h);
  double turn = 0;  // the course's largest departure from its first value [deg]
  for (double c : course) turn = std::max(turn, std::abs(wrap_pi(c - course.front())) / kDegToRad);
  if (n >= kMinUnitSamples && h_lo == h_hi && turn > kMinHeadingTurnDeg)
    throw ConfigError("observer.csv heading_deg is " + num(h_lo) + " in every row while the observer's course over "
                      "ground turns by " + num(turn) + " deg: no compass behind the column (leave it empty where "
                      "there is no heading)");
  if (bearings_look_like_radians(n, inside, refs, refs_outside))
    throw ConfigError("observer.csv heading_deg looks like radians: all " + std::to_string(n) +
                      " values lie within [0, 6.28] while the observer's course over ground mostly lies outside (" +
                      std::to_string(refs_outside) + " of " + std::to_string(refs) + " moving steps)");
}

// One time scale for the folder, after each time's own checks (validate): the detections and
// each target's reference on observer.csv's (plausible::same_time_scale: milliseconds,
// microseconds, epoch against relative, no overlap at all).
void check_time_scales(const MultiSensorData& d) {
  std::vector<double> obs_t, det_t;
  for (const auto& s : d.observer) obs_t.push_back(s.t_s);
  for (const auto& x : d.detections) det_t.push_back(x.t_s);
  plausible::same_time_scale("detections.csv t_s", det_t, "observer.csv t_s", obs_t);
  for (const auto& [name, v] : d.truth) {
    std::vector<double> t;
    for (const auto& s : v) t.push_back(s.t_s);
    plausible::same_time_scale("truth.csv t_s (target " + name + ")", t, "observer.csv t_s", obs_t);
  }
}

}  // namespace

MultiSensorData MultiSensorData::read_folder(const std::string& dir) {
  MultiSensorData d;
  refuse_raw_autoferry(dir);
  read_observer(dir + "/observer.csv", d);
  read_detections(dir + "/detections.csv", d);
  if (std::filesystem::exists(dir + "/truth.csv")) read_truth(dir + "/truth.csv", d);
  if (std::filesystem::exists(dir + "/targets.csv")) read_targets(dir + "/targets.csv", d);
  check_units(d);
  d.validate(dir);
  check_time_scales(d);
  return d;
}

void MultiSensorData::validate(const std::string& source) const {
  namespace pl = plausible;
  const Geodetic* first = observer.empty() ? nullptr : &observer[0].g;
  pl::track(source + ": observer sample", observer, first, "the observer's first position", pl::Heights::kAll);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& x = detections[i];
    const std::string at = source + ": detection " + std::to_string(i) + " (sensor " + x.sensor + ")";
    pl::time(at, x.t_s);
    if (!std::isnan(x.range_m) && x.range_m != 0) pl::range(at, x.range_m);  // 0: a detection at the sensor
    if (!std::isnan(x.bearing_rad)) pl::angle(at, "bearing", x.bearing_rad);
    if (!std::isnan(x.elevation_rad)) pl::angle(at, "elevation", x.elevation_rad);
  }
  for (const auto& [name, v] : truth)
    pl::track(source + ": truth of target " + name + " sample", v, first, "the observer's first position",
              pl::Heights::kWhereKnown);
}

std::vector<CsvColumnDoc> MultiSensorData::observer_columns(bool heading) {
  auto c = geo_track_columns("time of validity, the recording's time scale (one for every file of the folder)",
                             "the observer's (ownship's) navigation solution's");
  if (heading) c.push_back({"heading_deg", "deg", "the observer's heading, clockwise from true north, [0, 360); empty where unknown"});
  return c;
}

std::vector<CsvColumnDoc> MultiSensorData::detections_columns(bool elevation) {
  std::vector<CsvColumnDoc> c{
      {"t_s", "s", "time of the sensor's scan, the recording's time scale"},
      {"sensor", "", "sensor name"},
      {"range_m", "m", "range from the observer to the detection; empty for a bearing-only sensor and an empty scan"},
      {"bearing_deg", "deg", "true bearing from the observer to the detection, clockwise from north; empty for an empty scan"}};
  if (elevation) c.push_back({"elevation_deg", "deg", "elevation of the detection above the observer's horizontal; empty if none"});
  return c;
}

std::vector<CsvColumnDoc> MultiSensorData::targets_columns() {
  return {{"target", "", "target name (as in truth.csv)"},
          {"length_m", "m", "the hull's length overall (AIS: A + B), (0, 1000]; 0 or empty where unknown"},
          {"beam_m", "m", "the hull's beam (AIS: C + D), (0, 1000]; 0 or empty where unknown"}};
}

std::vector<CsvColumnDoc> MultiSensorData::truth_columns(bool height) {
  auto c = geo_track_columns("time of validity, the recording's time scale", "the target's reference (true)", height);
  c.insert(c.begin() + 1, {"target", "", "target name"});
  if (height) c.back().meaning += "; empty where unknown";
  return c;
}

void MultiSensorData::write_folder(const std::string& dir) const {
  if (!observer_heading_deg.empty() && observer_heading_deg.size() != observer.size())
    throw std::invalid_argument("MultiSensorData: observer_heading_deg has " +
                                std::to_string(observer_heading_deg.size()) + " values for " +
                                std::to_string(observer.size()) + " observer rows");
  for (const auto& x : detections)
    if (!valid_sensor_name(x.sensor)) throw ConfigError("MultiSensorData: '" + x.sensor + "' is not a sensor name");
  for (const auto& [name, v] : truth)
    if (!valid_target_name(name)) throw ConfigError("MultiSensorData: '" + name + "' is not a target name");
  std::filesystem::create_directories(dir);
  {
    const bool hdg = any_finite(observer_heading_deg);
    CheckedFile f(dir + "/observer.csv", observer_columns(hdg));
    for (std::size_t i = 0; i < observer.size(); ++i) {
      const auto& s = observer[i];
      f.out() << cell(s.t_s, 6) << ',' << cell(s.g.lat_deg, 10) << ',' << cell(s.g.lon_deg, 10) << ','
              << cell(s.g.h_m, 4);
      if (hdg) f.out() << ',' << cell(observer_heading_deg[i], 6);
      f.out() << '\n';
    }
    f.close();
  }
  {
    const bool elev = std::any_of(detections.begin(), detections.end(),
                                  [](const Detection& x) { return !std::isnan(x.elevation_rad); });
    CheckedFile f(dir + "/detections.csv", detections_columns(elev));
    for (const auto& x : detections) {
      f.out() << cell(x.t_s, 6) << ',' << x.sensor << ',' << cell(x.range_m, 3) << ','
              << cell(x.bearing_rad / kDegToRad, 6);
      if (elev) f.out() << ',' << cell(x.elevation_rad / kDegToRad, 6);
      f.out() << '\n';
    }
    f.close();
  }
  const std::string targets_file = dir + "/targets.csv";
  if (hull.empty()) {
    std::filesystem::remove(targets_file);  // no stale hull sizes from an earlier write
    std::filesystem::remove(csv_units_name(targets_file));
  } else {
    for (const auto& [name, h] : hull) {
      if (!valid_target_name(name)) throw ConfigError("MultiSensorData: '" + name + "' is not a target name (hull)");
      for (double x : {h.length_m, h.beam_m})
        if (!std::isnan(x) && !(x > 0 && x <= kMaxHullM))
          throw ConfigError("MultiSensorData: hull of target " + name + " must be in (0, 1000] m or unknown (NaN), got " +
                            num(x));
    }
    CheckedFile f(targets_file, targets_columns());
    for (const auto& [name, h] : hull) f.out() << name << ',' << cell(h.length_m, 2) << ',' << cell(h.beam_m, 2) << '\n';
    f.close();
  }
  const std::string truth_file = dir + "/truth.csv";
  if (truth.empty()) {
    std::filesystem::remove(truth_file);  // no stale truth from an earlier write
    std::filesystem::remove(csv_units_name(truth_file));
    return;
  }
  bool h = false;
  for (const auto& [name, v] : truth)
    for (const auto& s : v) h = h || !std::isnan(s.g.h_m);
  CheckedFile f(truth_file, truth_columns(h));
  for (const auto& [name, v] : truth)
    for (const auto& s : v) {
      f.out() << cell(s.t_s, 6) << ',' << name << ',' << cell(s.g.lat_deg, 10) << ',' << cell(s.g.lon_deg, 10);
      if (h) f.out() << ',' << cell(s.g.h_m, 4);
      f.out() << '\n';
    }
  f.close();
}

}  // namespace rnav
