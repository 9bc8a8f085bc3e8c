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
// The conversion (frames, checks) is autoferry_import.hpp; this main only wires options to it.
#include "atomic_file.hpp"
#include "autoferry_import.hpp"
#include "config.hpp"

#include <iostream>
#include <map>

namespace {

const char* const kUsage =
    "usage: rnav_import_autoferry SCENARIO_DIR --out DIR\n"
    "         all four sensors (radar, lidar, eo, ir) and both targets (1, 2) in the\n"
    "         multi-sensor format: observer.csv, detections.csv, truth.csv\n"
    "       rnav_import_autoferry SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR\n"
    "         one camera's bearings and one target's truth in the azimuth-only format:\n"
    "         observer.csv, bearings.csv, truth.csv\n"
    "SCENARIO_DIR holds NAME_detections.json and NAME_groundTruth.json, NAME = its folder name.\n"
    "DIR must be new, empty or an earlier output (its .rnav-output marker); --force writes into any.\n";

/// Counts of what was imported, on stderr.
void report(const rnav::AzimuthData& d, int target) {
  std::cerr << "import: " << d.observer.size() << " observer rows, " << d.frames.size()
            << " frames with detections, " << d.truth.size() << " truth samples of target " << target << "\n";
}
void report(const rnav::MultiSensorData& d) {
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
    if (!sensor.empty() && sensor != "eo" && sensor != "ir")
      throw rnav::ConfigError("import: --sensor must be eo or ir, got '" + sensor + "'");
    const rnav::AutoferryRecords records = rnav::load_autoferry(dir);
    if (sensor.empty() && target.empty()) {
      const rnav::MultiSensorData d = rnav::autoferry_to_multi(records);
      d.write_folder(out);
      rnav::MultiSensorData::read_folder(out);  // what was written must read back
      report(d);
      return 0;
    }
    const int tgt = target.empty() ? 1 : static_cast<int>(rnav::parse_integer("--target", target, 1, 2));
    const rnav::AzimuthData d = rnav::autoferry_to_azimuth(records, sensor.empty() ? "eo" : sensor, tgt);
    d.write_folder(out);
    report(d, tgt);
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 1;
  }
}
