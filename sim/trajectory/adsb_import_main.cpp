// rnav_import_adsb: an ADS-B flight (JSON or JSON.gz records, see adsb_records.hpp) -> the
// approaches it flies towards a runway (--list) or one of them as a replay CSV for
// trajectory.replay_csv (--approach N --out FILE.csv).
//
// Usage: rnav_import_adsb FILE (--list | --approach N --out FILE.csv [--lead-s S] [--end-x-m X]) [options]
//   runway (default: our scenario's LOWW 29, common/scenario.hpp RunwayOptions):
//     --scenario FILE          take runway.threshold_* and runway.heading_deg from a scenario
//     --threshold LAT,LON,H_M  threshold [deg, deg, m above WGS84]   --heading-deg H  landing true heading [deg]
//   height (baro altitude is not ellipsoidal height: QNH and geoid undulation are unknown):
//     --height-source baro|geo barometric altitude (default; in every file) or geoaltitude (GNSS)
//     --height-offset-m M      h_m = height_ft * 0.3048 + M   (default: fitted per approach so its
//                              glide path crosses the threshold at --glide-path-tch-m, default 15 m)
//   glitches (adsb_glitches.hpp): --max-speed-kt 400 --max-vertical-rate-fpm 6000
//                                 --altitude-tolerance-ft 300 --max-reject-run-s 60
//   approaches (adsb_approaches.hpp): --course-tolerance-deg 15 --min-descent-m 150
//                                     --min-duration-s 60 --max-gap-s 30
//   --lead-s S                 also write the S seconds of flight before the approach (default 0)
//   --end-x-m X                stop the export before the first point with x < X in the landing frame
//                              (e.g. 0: at the threshold; default: at the approach's lowest point)
//   --force                    replace an existing --out file (without it, an existing file is an error)
// Prints how many records each glitch rule removed to stderr. Exit status: 0 ok, 2 bad input.
#include "adsb_approaches.hpp"
#include "scenario.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace {

double number(const std::string& opt, const std::string& v) {
  std::size_t pos = 0;
  double x = NAN;
  try {
    x = std::stod(v, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (v.empty() || pos != v.size() || !std::isfinite(x))
    throw rnav::ConfigError("import: " + opt + " '" + v + "' is not a finite number");
  return x;
}

rnav::Geodetic threshold(const std::string& v) {
  std::stringstream ss(v);
  std::vector<double> x;
  for (std::string c; std::getline(ss, c, ',');) x.push_back(number("--threshold", c));
  if (x.size() != 3) throw rnav::ConfigError("import: --threshold needs LAT,LON,H_M, got '" + v + "'");
  if (std::abs(x[0]) > 90 || std::abs(x[1]) > 180)
    throw rnav::ConfigError("import: --threshold latitude/longitude out of range: '" + v + "'");
  return {x[0], x[1], x[2]};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2 || std::string(argv[1]).rfind("--", 0) == 0)
      throw rnav::ConfigError("usage: rnav_import_adsb FILE (--list | --approach N --out FILE.csv [--lead-s S] [--end-x-m X]) "
                              "[options] (see the head of sim/trajectory/adsb_import_main.cpp)");
    const std::string file = argv[1];
    rnav::GlitchOptions g;
    rnav::ApproachSearchOptions a;
    std::string scenario, out, thr, heading;
    bool list = false, force = false;
    long approach = 0;
    rnav::ReplayExportOptions ex;
    for (int i = 2; i < argc; ++i) {
      const std::string o = argv[i];
      if (o == "--list") { list = true; continue; }
      if (o == "--force") { force = true; continue; }
      if (i + 1 >= argc) throw rnav::ConfigError("import: option " + o + " needs a value");
      const std::string v = argv[++i];
      if (o == "--scenario") scenario = v;
      else if (o == "--threshold") thr = v;
      else if (o == "--heading-deg") heading = v;
      else if (o == "--height-source") {
        if (v != "baro" && v != "geo") throw rnav::ConfigError("import: --height-source must be baro or geo");
        g.height = a.height = v == "baro" ? rnav::HeightSource::baro : rnav::HeightSource::geo;
      }
      else if (o == "--height-offset-m") a.height_offset_m = number(o, v);
      else if (o == "--glide-path-tch-m") a.glide_path_tch_m = number(o, v);
      else if (o == "--max-speed-kt") g.max_speed_kt = number(o, v);
      else if (o == "--max-vertical-rate-fpm") g.max_vertical_rate_fpm = number(o, v);
      else if (o == "--altitude-tolerance-ft") g.altitude_tolerance_ft = number(o, v);
      else if (o == "--max-reject-run-s") g.max_reject_run_s = number(o, v);
      else if (o == "--course-tolerance-deg") a.course_tolerance_deg = number(o, v);
      else if (o == "--min-descent-m") a.min_descent_m = number(o, v);
      else if (o == "--min-duration-s") a.min_duration_s = number(o, v);
      else if (o == "--max-gap-s") a.max_gap_s = number(o, v);
      else if (o == "--approach") approach = static_cast<long>(rnav::parse_integer(o, v, 1, 1000000));
      else if (o == "--out") out = v;
      else if (o == "--lead-s") ex.lead_s = number(o, v);
      else if (o == "--end-x-m") ex.end_x_m = number(o, v);
      else throw rnav::ConfigError("import: unknown option " + o);
    }
    if (list == (approach > 0)) throw rnav::ConfigError("import: give exactly one of --list and --approach N");
    if (approach > 0 && out.empty()) throw rnav::ConfigError("import: --approach needs --out FILE.csv");
    if (!out.empty() && !force && std::filesystem::exists(std::filesystem::symlink_status(out)))
      throw rnav::ConfigError("import: --out " + out + " exists; pass --force to replace it");
    if (ex.lead_s < 0) throw rnav::ConfigError("import: --lead-s must be >= 0");
    if (!scenario.empty()) {
      const auto sc = rnav::Scenario::load(scenario);
      a.threshold = sc.runway.threshold;
      a.heading_deg = sc.runway.heading_deg;
    }
    if (!thr.empty()) a.threshold = threshold(thr);
    if (!heading.empty()) a.heading_deg = number("--heading-deg", heading);

    const auto records = rnav::read_adsb_file(file);
    const auto clean = rnav::remove_glitches(records, g, file);
    std::cerr << "import: " << file << ": " << records.size() << " records, " << clean.removed_total()
              << " removed as glitches (";
    bool first = true;
    for (const auto& [rule, n] : clean.removed) std::cerr << (first ? "" : ", ") << rule << " " << n, first = false;
    std::cerr << "), " << clean.kept.size() << " kept\n";
    const auto found = rnav::find_approaches(clean.kept, a);
    std::cerr << "import: " << found.size() << " approach(es) on course " << a.heading_deg
              << " deg +- " << a.course_tolerance_deg << " deg; threshold " << a.threshold.lat_deg << ", "
              << a.threshold.lon_deg << ", " << a.threshold.h_m << " m; height "
              << (a.height == rnav::HeightSource::baro ? "baro" : "geo") << " + "
              << (a.height_offset_m ? std::to_string(*a.height_offset_m) + " m" : std::string("fitted offset"))
              << "\n";
    if (list) {
      rnav::print_approach_table(std::cout, found);
      return 0;
    }
    if (approach > static_cast<long>(found.size()))
      throw rnav::ConfigError("import: --approach " + std::to_string(approach) + ": only " +
                              std::to_string(found.size()) + " approach(es) found (see --list)");
    const auto& ap = found[static_cast<std::size_t>(approach - 1)];
    const std::size_t rows = rnav::write_replay_csv(out, clean.kept, ap, a, ex);
    std::cerr << "import: approach " << approach << " (" << ap.t_end_s - ap.t_start_s << " s, "
              << ap.dist_start_m << " m -> " << ap.dist_end_m << " m from the threshold, height offset "
              << ap.offset_m << " m) with " << ex.lead_s << " s lead, ending before x = " << ex.end_x_m << " m: " << rows << " rows -> " << out << "\n";
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "import: error: " << e.what() << "\n";
    return 1;
  }
}
