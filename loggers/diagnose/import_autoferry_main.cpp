// rnav_import_autoferry: one scenario of the Autoferry dataset (../shared/data/autoferry) into a
// CSV folder, in one of two modes:
//   rnav_import_autoferry SCENARIO_DIR --out DIR
//     the multi-sensor format (estimators/diagnosis/multi_sensor_data.hpp): the ferry's
//     positions (observer.csv), every scan of the radar, lidar, EO and IR with its detections
//     (detections.csv; an empty row for a scan without detection) and both boats' GNSS truth,
//     de-duplicated (truth.csv, targets "1" and "2").
//   rnav_import_autoferry SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR
//     the azimuth-only format (azimuth_data.hpp): the ferry's positions at that camera's frames,
//     all its bearings with their clutter and one target's truth. (Either option alone selects
//     this mode; the other defaults to eo / 1.)
// Frames: Piren NED (origin 63.4389029083 N, 10.39908278 E, 39.923 m; x north, y east) to WGS84
// through the local level frame at that origin (bearing 0: its x is north, y up, z east); times
// stay Unix seconds (the multi-sensor mode rounds them to the microsecond it writes).
#include "azimuth_data.hpp"
#include "atomic_file.hpp"
#include "config.hpp"
#include "multi_sensor_data.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace {

using nlohmann::json;

const char* const kUsage =
    "usage: rnav_import_autoferry SCENARIO_DIR --out DIR\n"
    "         all four sensors (radar, lidar, eo, ir) and both targets (1, 2) in the\n"
    "         multi-sensor format: observer.csv, detections.csv, truth.csv\n"
    "       rnav_import_autoferry SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR\n"
    "         one camera's bearings and one target's truth in the azimuth-only format:\n"
    "         observer.csv, bearings.csv, truth.csv\n"
    "SCENARIO_DIR holds NAME_detections.json and NAME_groundTruth.json, NAME = its folder name.\n"
    "DIR must be new, empty or an earlier output (its .rnav-output marker); --force writes into any.\n";

const rnav::LocalLevelFrame& piren() {
  static const rnav::LocalLevelFrame f({63.4389029083, 10.39908278, 39.923}, 0.0);
  return f;
}
/// WGS84 position of Piren NED (north n, east e, down d) [m].
rnav::Geodetic piren_geo(double n, double e, double d = 0.0) {
  return piren().to_geodetic(Eigen::Vector3d(n, -d, e));
}

// ---- JSON values checked before use (both modes) ----
/// Throws ConfigError "WHERE: WHAT".
[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw rnav::ConfigError(where + ": " + what);
}
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


// ---- the azimuth-only mode (unchanged behaviour; scripts/autoferry_study uses it) ----
int import_azimuth(const std::string& dir, const std::string& sensor, int target, const std::string& out) {
  if (sensor != "eo" && sensor != "ir") throw rnav::ConfigError("import: --sensor must be eo or ir");
  if (target != 1 && target != 2) throw rnav::ConfigError("import: --target must be 1 or 2");
  const std::string name = std::filesystem::path(dir).filename().string();
  const auto det = rnav::load_json_file(dir + "/" + name + "_detections.json");
  const auto gt = rnav::load_json_file(dir + "/" + name + "_groundTruth.json");
  if (!det.is_array() || !gt.is_array() || det.size() != gt.size())
    throw rnav::ConfigError(dir + ": detections and ground truth must be arrays of equal length");
  auto geo = [&](double n, double e) { return piren_geo(n, e); };
  const int sid = sensor == "eo" ? 4 : 3;
  rnav::AzimuthData d;
  std::map<double, std::pair<double, double>> truth;
  for (std::size_t i = 0; i < det.size(); ++i) {
    const auto& r = det[i];
    const std::string where = dir + " record " + std::to_string(i);
    if (!r.is_object()) bad(where, "not an object");
    if (!gt[i].is_array()) bad(dir + " ground-truth record " + std::to_string(i), "not a list");
    for (const auto& g : gt[i]) {
      const std::string gw = dir + " ground-truth record " + std::to_string(i);
      if (!g.is_object()) bad(gw, "an entry is not an object");
      if (finite(member(g, "targetID", gw), gw, "targetID") != target) continue;
      const auto pos = finite_list(member(g, "position", gw), gw, "position");
      if (pos.size() < 2) bad(gw, "position has " + std::to_string(pos.size()) + " numbers, not [N, E(, D)]");
      truth[finite(member(g, "time", gw), gw, "time")] = {pos[0], pos[1]};
    }
    if (finite(member(r, "sensorID", where), where, "sensorID") != sid) continue;
    const double t = finite(member(r, "time", where), where, "time");
    const auto own = finite_list(member(r, "ownshipPosition", where), where, "ownshipPosition");
    if (own.size() != 2) bad(where, "ownshipPosition has " + std::to_string(own.size()) + " numbers, not 2 [N, E]");
    if (!d.observer.empty() && t <= d.observer.back().t_s) continue;  // keep time order per sensor
    d.observer.push_back({t, geo(own[0], own[1])});
    const auto& m = member(r, "measurement", where);
    rnav::BearingFrame f{t, {}};
    if (m.is_number()) f.bearings_rad.push_back(finite(m, where, "measurement"));
    else if (m.is_array()) f.bearings_rad = finite_list(m, where, "measurement");
    else bad(where, "measurement is neither a number nor a list");
    if (!f.bearings_rad.empty()) d.frames.push_back(f);
  }
  for (const auto& [t, p] : truth) {
    const auto g = geo(p.first, p.second);
    d.truth.push_back({t, {g.lat_deg, g.lon_deg, 0.0}});
  }
  d.write_folder(out);
  std::cerr << "import: " << d.observer.size() << " observer rows, " << d.frames.size()
            << " frames with detections, " << d.truth.size() << " truth samples of target " << target << "\n";
  return 0;
}

// ---- the multi-sensor mode: every JSON value checked before use ----

/// Rounded to the microsecond that the CSV files hold [s].
double to_us(double t_s) { return std::round(t_s * 1e6) / 1e6; }

/// The detections of one record: sensor 1 (lidar) / 2 (radar) as Cartesian offsets
/// [] | [N, E] | [[N1..NM], [E1..EM]] in ownship-fixed NED [m]; 3 (IR) / 4 (EO) as bearings
/// b | [b1..bM] [rad], clockwise from north.
void add_measurement(const json& m, int sid, double t, const std::string& where, rnav::MultiSensorData& d) {
  static const std::map<int, std::string> kName = {{1, "lidar"}, {2, "radar"}, {3, "ir"}, {4, "eo"}};
  rnav::Detection x{t, kName.at(sid), NAN, NAN, NAN};
  const std::size_t before = d.detections.size();
  if (sid >= 3) {
    const std::vector<double> b = m.is_number() ? std::vector<double>{finite(m, where, "measurement")}
                                                : finite_list(m, where, "measurement");
    for (double v : b) {
      if (std::abs(v) > 2 * M_PI) bad(where, "bearing " + std::to_string(v) + " rad is outside [-2pi, 2pi]");
      x.bearing_rad = rnav::wrap_pi(v);
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
      bad(where, "radar/lidar measurement must be [], [N, E] or [[N...], [E...]], has " +
                     std::to_string(m.size()) + " elements");
    }
    for (std::size_t k = 0; k < n.size(); ++k) {
      x.range_m = std::hypot(n[k], e[k]);
      if (x.range_m > 1e6) bad(where, "detection " + std::to_string(k) + " is farther than 1e6 m");
      x.bearing_rad = rnav::wrap_pi(std::atan2(e[k], n[k]));
      d.detections.push_back(x);
    }
  }
  if (d.detections.size() == before) d.detections.push_back({t, x.sensor, NAN, NAN, NAN});  // empty scan
}

int import_multi(const std::string& dir, const std::string& out) {
  const std::string name = std::filesystem::path(dir).filename().string();
  const std::string det_file = dir + "/" + name + "_detections.json", gt_file = dir + "/" + name + "_groundTruth.json";
  const auto det = rnav::load_json_file(det_file);
  const auto gt = rnav::load_json_file(gt_file);
  if (!det.is_array()) bad(det_file, "not a JSON array");
  if (!gt.is_array()) bad(gt_file, "not a JSON array");
  if (det.size() != gt.size())
    bad(gt_file, std::to_string(gt.size()) + " elements, the detections have " + std::to_string(det.size()));
  rnav::MultiSensorData d;
  std::map<double, std::array<double, 2>> own;                 // time [s] -> ownship N, E [m]
  std::map<int, std::map<double, std::array<double, 3>>> truth;  // target -> time -> N, E, D [m]
  std::map<int, double> last_t;                                // sensorID -> latest time
  for (std::size_t i = 0; i < det.size(); ++i) {
    const std::string where = det_file + " record " + std::to_string(i);
    const json& r = det[i];
    if (!r.is_object()) bad(where, "not an object");
    const json& sid_j = member(r, "sensorID", where);
    if (!sid_j.is_number_integer()) bad(where, "sensorID is not an integer");
    const int sid = sid_j.get<int>();
    if (sid < 1 || sid > 4) bad(where, "unknown sensorID " + std::to_string(sid) + " (1 lidar, 2 radar, 3 IR, 4 EO)");
    const double t = to_us(finite(member(r, "time", where), where, "time"));
    const auto p = finite_list(member(r, "ownshipPosition", where), where, "ownshipPosition");
    if (p.size() != 2) bad(where, "ownshipPosition has " + std::to_string(p.size()) + " numbers, not 2 [N, E]");
    const auto lt = last_t.find(sid);
    if (lt != last_t.end() && t <= lt->second)
      bad(where, "time " + rnav::fixed(t) + " is not after the previous record of sensorID " + std::to_string(sid) +
                     " (" + rnav::fixed(lt->second) + ")");
    last_t[sid] = t;
    own.emplace(t, std::array<double, 2>{p[0], p[1]});  // the first record of a time wins
    add_measurement(member(r, "measurement", where), sid, t, where, d);

    const std::string gwhere = gt_file + " element " + std::to_string(i);
    if (!gt[i].is_array()) bad(gwhere, "not a list of {targetID, position, time} objects");
    for (std::size_t k = 0; k < gt[i].size(); ++k) {
      const std::string w = gwhere + " item " + std::to_string(k);
      const json& g = gt[i][k];
      if (!g.is_object()) bad(w, "not an object");
      const json& id = member(g, "targetID", w);
      if (!id.is_number_integer() || id.get<long>() < 0 || id.get<long>() > 1000000)
        bad(w, "targetID is not an integer in [0, 1e6]");
      const auto pos = finite_list(member(g, "position", w), w, "position");
      if (pos.size() != 3) bad(w, "position has " + std::to_string(pos.size()) + " numbers, not 3 [N, E, D]");
      const double tt = to_us(finite(member(g, "time", w), w, "time"));
      const auto [it, fresh] = truth[id.get<int>()].emplace(tt, std::array<double, 3>{pos[0], pos[1], pos[2]});
      if (!fresh && it->second != std::array<double, 3>{pos[0], pos[1], pos[2]})
        bad(w, "target " + std::to_string(id.get<int>()) + " at time " + rnav::fixed(tt) +
                   " differs from an earlier element's position");
    }
  }
  for (const auto& [t, p] : own) d.observer.push_back({t, piren_geo(p[0], p[1])});
  for (const auto& [id, v] : truth)
    for (const auto& [t, p] : v) d.truth[std::to_string(id)].push_back({t, piren_geo(p[0], p[1], p[2])});
  d.write_folder(out);
  rnav::MultiSensorData::read_folder(out);  // what was written must read back

  std::map<std::string, std::pair<std::size_t, std::size_t>> count;  // sensor -> scans, detections
  std::map<std::string, double> last_scan;
  for (const auto& x : d.detections) {
    auto& c = count[x.sensor];
    const auto it = last_scan.find(x.sensor);
    if (it == last_scan.end() || it->second != x.t_s) ++c.first;
    last_scan[x.sensor] = x.t_s;
    if (!x.empty_scan()) ++c.second;
  }
  std::cerr << "import: observer: " << d.observer.size() << " positions\n";
  for (const auto& [s, c] : count)
    std::cerr << "import: sensor " << s << ": " << c.first << " scans, " << c.second << " detections\n";
  for (const auto& [id, v] : d.truth) std::cerr << "import: target " << id << ": " << v.size() << " truth samples\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    for (int i = 1; i < argc; ++i)
      if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
        std::cout << kUsage;
        return 0;
      }
    if (argc < 2) throw rnav::ConfigError(std::string("no SCENARIO_DIR\n") + kUsage);
    const std::string dir = argv[1];
    std::string sensor, out, target;
    bool force = false;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--force") {
        force = true;
        continue;
      }
      if (i + 1 >= argc) throw rnav::ConfigError("import: option " + a + " needs a value");
      if (a == "--sensor") sensor = argv[++i];
      else if (a == "--target") target = argv[++i];
      else if (a == "--out") out = argv[++i];
      else throw rnav::ConfigError("import: unknown option " + a);
    }
    if (out.empty()) throw rnav::ConfigError("import: --out DIR is required");
    rnav::prepare_output_dir(out, force);
    if (sensor.empty() && target.empty()) return import_multi(dir, out);
    return import_azimuth(dir, sensor.empty() ? "eo" : sensor, target.empty() ? 1 : static_cast<int>(rnav::parse_integer("--target", target, 1, 2)), out);
  } catch (const rnav::ConfigError& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 1;
  }
}
