// rnav_import_autoferry: one scenario of the Autoferry dataset (../shared/data/autoferry) into
// the azimuth-only CSV folder: the ferry's positions (observer.csv), all EO or IR bearings with
// their clutter (bearings.csv) and one target's GNSS truth, de-duplicated (truth.csv).
// Usage: rnav_import_autoferry SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR
// Frames: Piren NED (origin 63.4389029083 N, 10.39908278 E, 39.923 m; x north, y east) to WGS84
// through the local level frame at that origin; times stay Unix seconds.
#include "azimuth_data.hpp"
#include "config.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw rnav::ConfigError("usage: rnav_import_autoferry SCENARIO_DIR --sensor eo|ir --target 1|2 --out DIR");
    const std::string dir = argv[1];
    std::string sensor = "eo", out;
    int target = 1;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (i + 1 >= argc) throw rnav::ConfigError("import: option " + a + " needs a value");
      if (a == "--sensor") sensor = argv[++i];
      else if (a == "--target") target = std::stoi(argv[++i]);
      else if (a == "--out") out = argv[++i];
      else throw rnav::ConfigError("import: unknown option " + a);
    }
    if (sensor != "eo" && sensor != "ir") throw rnav::ConfigError("import: --sensor must be eo or ir");
    if (target != 1 && target != 2) throw rnav::ConfigError("import: --target must be 1 or 2");
    if (out.empty()) throw rnav::ConfigError("import: --out DIR is required");
    const std::string name = std::filesystem::path(dir).filename().string();
    const auto det = rnav::load_json_file(dir + "/" + name + "_detections.json");
    const auto gt = rnav::load_json_file(dir + "/" + name + "_groundTruth.json");
    if (!det.is_array() || !gt.is_array() || det.size() != gt.size())
      throw rnav::ConfigError(dir + ": detections and ground truth must be arrays of equal length");
    const rnav::LocalLevelFrame piren({63.4389029083, 10.39908278, 39.923}, 0.0);
    auto geo = [&](double n, double e) { return piren.to_geodetic(Eigen::Vector3d(n, 0.0, e)); };
    const int sid = sensor == "eo" ? 4 : 3;
    rnav::AzimuthData d;
    std::map<double, std::pair<double, double>> truth;
    for (std::size_t i = 0; i < det.size(); ++i) {
      const auto& r = det[i];
      const std::string where = dir + " record " + std::to_string(i);
      if (!r.contains("sensorID") || !r.contains("time") || !r.contains("ownshipPosition"))
        throw rnav::ConfigError(where + ": missing sensorID, time or ownshipPosition");
      for (const auto& g : gt[i])
        if (g.at("targetID").get<int>() == target)
          truth[g.at("time").get<double>()] = {g.at("position")[0].get<double>(), g.at("position")[1].get<double>()};
      if (r["sensorID"].get<int>() != sid) continue;
      const double t = r["time"].get<double>();
      const auto& own = r["ownshipPosition"];
      if (!d.observer.empty() && t <= d.observer.back().t_s) continue;  // keep time order per sensor
      d.observer.push_back({t, geo(own[0].get<double>(), own[1].get<double>())});
      const auto& m = r["measurement"];
      rnav::BearingFrame f{t, {}};
      if (m.is_number()) f.bearings_rad.push_back(m.get<double>());
      else if (m.is_array())
        for (const auto& b : m) f.bearings_rad.push_back(b.get<double>());
      else throw rnav::ConfigError(where + ": measurement is neither a number nor a list");
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
  } catch (const rnav::ConfigError& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 1;
  }
}
