#include "estimators/diagnosis/io/autoferry_import.hpp"

#include "common/io/atomic_file.hpp"
#include "common/physics/bearing.hpp"
#include "common/io/config.hpp"
#include "common/physics/frames.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <map>

namespace rnav {

namespace {

using nlohmann::json;

/// The Autoferry scenarios' local frame: Piren NED's origin, bearing 0 (x north, y up, z east).
const LocalLevelFrame& piren() {
  static const LocalLevelFrame f({63.4389029083, 10.39908278, 39.923}, 0.0);
  return f;
}
/// WGS84 position of Piren NED (north n, east e, down d) [m].
Geodetic piren_geo(double n, double e, double d = 0.0) { return piren().to_geodetic(Eigen::Vector3d(n, -d, e)); }

/// Throws ConfigError "WHERE: WHAT".
[[noreturn]] void bad(const std::string& where, const std::string& what) { throw ConfigError(where + ": " + what); }
/// v as a finite number, else ConfigError naming `what`.
double finite(const json& v, const std::string& where, const std::string& what) {
  if (!v.is_number()) bad(where, what + " is not a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) bad(where, what + " is not finite");
  return x;
}
/// Member `key` of object o, else ConfigError.
const json& member(const json& o, const char* key, const std::string& where) {
  const auto it = o.find(key);
  if (it == o.end()) bad(where, std::string("missing key '") + key + "'");
  return *it;
}
/// A list of finite numbers.
std::vector<double> finite_list(const json& v, const std::string& where, const std::string& what) {
  if (!v.is_array()) bad(where, what + " is not a list");
  std::vector<double> out;
  for (std::size_t k = 0; k < v.size(); ++k) out.push_back(finite(v[k], where, what + "[" + std::to_string(k) + "]"));
  return out;
}
/// An integer-valued number in [lo, hi] (the dataset writes IDs as JSON integers).
int integer(const json& v, const std::string& where, const std::string& what, int lo, int hi) {
  if (!v.is_number_integer()) bad(where, what + " is not an integer");
  const auto x = v.get<long long>();
  if (x < lo || x > hi)
    bad(where, what + " " + std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(x);
}
/// Both documents arrays of equal length.
void check_shape(const AutoferryRecords& r) {
  if (!r.detections.is_array()) bad(r.detections_name, "not a JSON array");
  if (!r.ground_truth.is_array()) bad(r.ground_truth_name, "not a JSON array");
  if (r.detections.size() != r.ground_truth.size())
    bad(r.ground_truth_name, std::to_string(r.ground_truth.size()) + " elements, the detections have " +
                                 std::to_string(r.detections.size()));
}

constexpr int kLidar = 1, kRadar = 2, kIr = 3, kEo = 4;  // the dataset's sensorID values
constexpr int kMaxTargetId = 1000000;

/// Rounded to the microsecond that the CSV files hold [s].
double to_us(double t_s) { return std::round(t_s * 1e6) / 1e6; }

/// A record's time [s]: the dataset stamps Unix seconds (1.62e9 in 2021). A time outside
/// [0, kMaxUnixS] is named on its own record (not as the next record's disorder): beyond it by
/// 10^3 or 10^6 as milliseconds or microseconds, else as out of range.
constexpr double kMaxUnixS = 4102444800;  // [s] 2100-01-01T00:00:00Z
double record_time(const json& rec, const std::string& where) {
  const double t = finite(member(rec, "time", where), where, "time");
  if (t >= 0 && t <= kMaxUnixS) return t;
  std::string why = "outside [0, " + fixed(kMaxUnixS, 0) + "] s (Unix seconds up to the year 2100)";
  if (t > kMaxUnixS && t / 1e3 <= kMaxUnixS) why += ": milliseconds?";
  else if (t > kMaxUnixS && t / 1e6 <= kMaxUnixS) why += ": microseconds?";
  char b[64];
  std::snprintf(b, sizeof b, "time %.6g is ", t);
  bad(where, b + why);
}

/// The detections of one record: lidar / radar as Cartesian offsets [] | [N, E] |
/// [[N1..NM], [E1..EM]] in ownship-fixed NED [m]; IR / EO as bearings b | [b1..bM] [rad],
/// clockwise from north.
void add_measurement(const json& m, int sid, double t, const std::string& where, MultiSensorData& d) {
  static const std::map<int, std::string> kName = {{kLidar, "lidar"}, {kRadar, "radar"}, {kIr, "ir"}, {kEo, "eo"}};
  Detection x{t, kName.at(sid), NAN, NAN, NAN};
  const std::size_t before = d.detections.size();
  if (sid == kIr || sid == kEo) {
    const std::vector<double> b =
        m.is_number() ? std::vector<double>{finite(m, where, "measurement")} : finite_list(m, where, "measurement");
    for (double v : b) {
      if (std::abs(v) > 2 * M_PI) bad(where, "bearing " + value_text(v) + " rad is outside [-2pi, 2pi]");
      x.bearing_rad = wrap_pi(v);
      d.detections.push_back(x);
    }
  } else {
    if (!m.is_array()) bad(where, "radar/lidar measurement is not a list");
    std::vector<double> n, e;
    if (m.size() == 2 && m[0].is_array() && m[1].is_array()) {
      n = finite_list(m[0], where, "measurement[0]");
      e = finite_list(m[1], where, "measurement[1]");
      if (n.size() != e.size())
        bad(where, "measurement rows differ in length (" + std::to_string(n.size()) + " north, " +
                       std::to_string(e.size()) + " east)");
    } else if (m.size() == 2) {
      n = {finite(m[0], where, "measurement[0]")};
      e = {finite(m[1], where, "measurement[1]")};
    } else if (!m.empty()) {
      bad(where, "radar/lidar measurement must be [], [N, E] or [[N...], [E...]], has " + std::to_string(m.size()) +
                     " elements");
    }
    for (std::size_t k = 0; k < n.size(); ++k) {
      x.range_m = std::hypot(n[k], e[k]);
      if (x.range_m > 1e6) bad(where, "detection " + std::to_string(k) + " is farther than 1e6 m");
      x.bearing_rad = wrap_pi(bearing_rad(Eigen::Vector2d(n[k], e[k])));
      d.detections.push_back(x);
    }
  }
  if (d.detections.size() == before) d.detections.push_back({t, x.sensor, NAN, NAN, NAN});  // empty scan
}

}  // namespace

AutoferryRecords load_autoferry(const std::string& dir) {
  const std::string name = std::filesystem::path(dir).filename().string();
  AutoferryRecords r;
  r.detections_name = dir + "/" + name + "_detections.json";
  r.ground_truth_name = dir + "/" + name + "_groundTruth.json";
  r.detections = load_json_file(r.detections_name);
  r.ground_truth = load_json_file(r.ground_truth_name);
  return r;
}

MultiSensorData autoferry_to_multi(const AutoferryRecords& r) {
  check_shape(r);
  MultiSensorData d;
  std::map<double, std::array<double, 2>> own;                 // time [s] -> ownship N, E [m]
  std::map<int, std::map<double, std::array<double, 3>>> truth;  // target -> time -> N, E, D [m]
  std::map<int, double> last_t;                                // sensorID -> latest time
  for (std::size_t i = 0; i < r.detections.size(); ++i) {
    const std::string where = r.detections_name + " record " + std::to_string(i);
    const json& rec = r.detections[i];
    if (!rec.is_object()) bad(where, "not an object");
    const json& sid_j = member(rec, "sensorID", where);
    if (!sid_j.is_number_integer()) bad(where, "sensorID is not an integer");
    const long long sid_v = sid_j.get<long long>();
    if (sid_v < kLidar || sid_v > kEo)
      bad(where, "unknown sensorID " + std::to_string(sid_v) + " (1 lidar, 2 radar, 3 IR, 4 EO)");
    const int sid = static_cast<int>(sid_v);
    const double t = to_us(record_time(rec, where));
    const auto p = finite_list(member(rec, "ownshipPosition", where), where, "ownshipPosition");
    if (p.size() != 2) bad(where, "ownshipPosition has " + std::to_string(p.size()) + " numbers, not 2 [N, E]");
    const auto lt = last_t.find(sid);
    if (lt != last_t.end() && t <= lt->second)
      bad(where, "time " + fixed(t) + " is not after the previous record of sensorID " + std::to_string(sid) + " (" +
                     fixed(lt->second) + ")");
    last_t[sid] = t;
    own.emplace(t, std::array<double, 2>{p[0], p[1]});  // the first record of a time wins
    add_measurement(member(rec, "measurement", where), sid, t, where, d);

    const std::string gwhere = r.ground_truth_name + " element " + std::to_string(i);
    const json& gl = r.ground_truth[i];
    if (!gl.is_array()) bad(gwhere, "not a list of {targetID, position, time} objects");
    for (std::size_t k = 0; k < gl.size(); ++k) {
      const std::string w = gwhere + " item " + std::to_string(k);
      const json& g = gl[k];
      if (!g.is_object()) bad(w, "not an object");
      const int id = integer(member(g, "targetID", w), w, "targetID", 0, kMaxTargetId);
      const auto pos = finite_list(member(g, "position", w), w, "position");
      if (pos.size() != 3) bad(w, "position has " + std::to_string(pos.size()) + " numbers, not 3 [N, E, D]");
      const double tt = to_us(record_time(g, w));
      const std::array<double, 3> ned{pos[0], pos[1], pos[2]};
      const auto [it, fresh] = truth[id].emplace(tt, ned);
      if (!fresh && it->second != ned)
        bad(w, "target " + std::to_string(id) + " at time " + fixed(tt) + " differs from an earlier element's position");
    }
  }
  for (const auto& [t, p] : own) d.observer.push_back({t, piren_geo(p[0], p[1])});
  for (const auto& [id, v] : truth)
    for (const auto& [t, p] : v) d.truth[std::to_string(id)].push_back({t, piren_geo(p[0], p[1], p[2])});
  d.validate(r.detections_name + " (imported)");
  return d;
}

AzimuthData autoferry_to_azimuth(const AutoferryRecords& r, const std::string& sensor, int target) {
  if (sensor != "eo" && sensor != "ir") throw ConfigError("sensor must be eo or ir, got '" + sensor + "'");
  if (target != 1 && target != 2) throw ConfigError("target must be 1 or 2, got " + std::to_string(target));
  check_shape(r);
  const int sid = sensor == "eo" ? kEo : kIr;
  AzimuthData d;
  std::map<double, std::pair<double, double>> truth;  // time [s] -> target's N, E [m]
  for (std::size_t i = 0; i < r.detections.size(); ++i) {
    const json& rec = r.detections[i];
    const std::string where = r.detections_name + " record " + std::to_string(i);
    if (!rec.is_object()) bad(where, "not an object");
    const std::string gw = r.ground_truth_name + " element " + std::to_string(i);
    if (!r.ground_truth[i].is_array()) bad(gw, "not a list of {targetID, position, time} objects");
    for (const auto& g : r.ground_truth[i]) {
      if (!g.is_object()) bad(gw, "an entry is not an object");
      if (finite(member(g, "targetID", gw), gw, "targetID") != target) continue;
      const auto pos = finite_list(member(g, "position", gw), gw, "position");
      if (pos.size() < 2) bad(gw, "position has " + std::to_string(pos.size()) + " numbers, not [N, E(, D)]");
      truth[record_time(g, gw)] = {pos[0], pos[1]};
    }
    if (finite(member(rec, "sensorID", where), where, "sensorID") != sid) continue;
    const double t = record_time(rec, where);
    const auto own = finite_list(member(rec, "ownshipPosition", where), where, "ownshipPosition");
    if (own.size() != 2) bad(where, "ownshipPosition has " + std::to_string(own.size()) + " numbers, not 2 [N, E]");
    if (!d.observer.empty() && t <= d.observer.back().t_s) continue;  // keep time order per sensor
    d.observer.push_back({t, piren_geo(own[0], own[1])});
    const auto& m = member(rec, "measurement", where);
    BearingFrame f{t, {}};
    if (m.is_number()) f.bearings_rad.push_back(finite(m, where, "measurement"));
    else if (m.is_array()) f.bearings_rad = finite_list(m, where, "measurement");
    else bad(where, "measurement is neither a number nor a list");
    if (!f.bearings_rad.empty()) d.frames.push_back(f);
  }
  for (const auto& [t, p] : truth) {
    const auto g = piren_geo(p.first, p.second);
    d.truth.push_back({t, {g.lat_deg, g.lon_deg, 0.0}});
  }
  d.validate(r.detections_name + " (imported " + sensor + ")");
  return d;
}

}  // namespace rnav
