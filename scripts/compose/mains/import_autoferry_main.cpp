// rnav_import_autoferry: one scenario of the Autoferry dataset (test/data/autoferry) into a
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
// The conversion (frames, checks) is autoferry_import.hpp; this main only wires options to it
// (one table below; --help prints it).
#include "common/io/atomic_file.hpp"
#include "estimators/diagnosis/io/autoferry_import.hpp"
#include "common/io/cli.hpp"
#include "common/io/config.hpp"

#include <filesystem>
#include <iostream>
#include <map>

namespace {

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
  return rnav::cli::guarded_main("rnav_import_autoferry", [&]() -> int {
    std::string dir, sensor, out, target, boat_names;
    bool force = false;
    rnav::cli::Parser p("rnav_import_autoferry",
                        "SCENARIO_DIR --out DIR [--force]\n"
                        "SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR [--force]",
                        "One scenario of the Autoferry dataset (test/data/autoferry in the source tree) as a CSV folder. Without "
                        "--sensor and --target: all four sensors (radar, lidar, eo, ir) and both targets (1, 2) in "
                        "the multi-sensor format (observer.csv, detections.csv, truth.csv; for scripts/diagnose "
                        "multi). With either: one camera's bearings and one target's truth in the azimuth-only "
                        "format (observer.csv, bearings.csv, truth.csv; for scripts/diagnose uav); the other "
                        "defaults to eo / 1. Counts of what was imported go to stderr.");
    p.positionals("SCENARIO_DIR", "a folder holding NAME_detections.json and NAME_groundTruth.json, NAME = its folder name",
                  [&](const std::string& v) {
                    if (!dir.empty()) throw rnav::ConfigError("unexpected argument '" + v + "' (SCENARIO_DIR already given)");
                    dir = v;
                  });
    p.value("--out", "DIR", "output folder; it must be new, empty or an earlier output (its .rnav-output marker) unless --force",
            "required", out)
        .flag("--force", "write into --out DIR whatever it holds", force)
        .value("--sensor", "eo|ir", "azimuth-only format: the camera whose bearings are written", "eo (with --target)", sensor)
        .value("--target", "1|2", "azimuth-only format: the boat whose truth is written", "1 (with --sensor)", target)
        .value("--boat-names", "NAME1,NAME2",
               "multi-sensor format: the names of targets 1 and 2 (e.g. havfruen,gunnerus), so that recordings "
               "diagnosed together share a boat by name; [A-Za-z0-9_]+, distinct",
               "1,2", boat_names);
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (dir.empty()) throw rnav::ConfigError("SCENARIO_DIR is required (see rnav_import_autoferry --help)");
    if (out.empty()) throw rnav::ConfigError("--out DIR is required");
    if (!sensor.empty() && sensor != "eo" && sensor != "ir")
      throw rnav::ConfigError("--sensor must be eo or ir, got '" + sensor + "'");
    const int tgt = target.empty() ? 1 : static_cast<int>(rnav::parse_integer("--target", target, 1, 2));
    // Everything read and converted before --out is touched: a failed import leaves no folder
    // behind (and an earlier output as it was until the write).
    const rnav::AutoferryRecords records = rnav::load_autoferry(dir);
    if (!boat_names.empty() && !(sensor.empty() && target.empty()))
      throw rnav::ConfigError("--boat-names applies to the multi-sensor format (without --sensor and --target)");
    const bool existed = std::filesystem::exists(out);
    auto write = [&](auto&& body) {
      rnav::prepare_output_dir(out, force);
      try {
        body();
      } catch (...) {
        std::error_code ec;
        if (!existed) std::filesystem::remove_all(out, ec);  // nothing of a failed import left behind
        throw;
      }
    };
    if (sensor.empty() && target.empty()) {
      rnav::MultiSensorData d = rnav::autoferry_to_multi(records);
      if (!boat_names.empty()) {
        const auto comma = boat_names.find(',');
        const std::string n1 = boat_names.substr(0, comma), n2 = comma == std::string::npos ? "" : boat_names.substr(comma + 1);
        if (!rnav::valid_target_name(n1) || !rnav::valid_target_name(n2) || n1 == n2)
          throw rnav::ConfigError("--boat-names must be two distinct names [A-Za-z0-9_]+ separated by a comma, got '" + boat_names + "'");
        std::map<std::string, std::vector<rnav::GeoSample>> named;
        for (auto& [id, track] : d.truth) named[id == "1" ? n1 : id == "2" ? n2 : id] = std::move(track);
        d.truth = std::move(named);
      }
      write([&] {
        d.write_folder(out);
        rnav::MultiSensorData::read_folder(out);  // what was written must read back
      });
      report(d);
      return 0;
    }
    const rnav::AzimuthData d = rnav::autoferry_to_azimuth(records, sensor.empty() ? "eo" : sensor, tgt);
    write([&] { d.write_folder(out); });
    report(d, tgt);
    return 0;
  });
}
