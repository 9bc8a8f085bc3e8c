// rnav_import_adsb: an ADS-B flight (JSON or JSON.gz records, see adsb_records.hpp) -> the
// approaches it flies towards a runway (--list) or one of them as a replay CSV for
// trajectory.replay_csv (--approach N --out FILE.csv).
//
// Options: one table below (rnav_import_adsb --help prints it). Prints how many records each
// glitch rule removed to stderr. Exit status: 0 ok, 2 bad input.
#include "sim/trajectory/adsb_approaches.hpp"
#include "common/io/cli.hpp"
#include "scripts/compose/scenario/scenario.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

namespace {

// A finite number from an option's text, else an error naming the option.
double number(const std::string& opt, const std::string& v) {
  return rnav::cli::number(opt, v, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
}

rnav::Geodetic threshold(const std::string& v) {
  std::stringstream ss(v);
  std::vector<double> x;
  for (std::string c; std::getline(ss, c, ',');) x.push_back(number("--threshold", c));
  if (x.size() != 3) throw rnav::ConfigError("--threshold needs LAT,LON,H_M, got '" + v + "'");
  if (std::abs(x[0]) > 90 || std::abs(x[1]) > 180)
    throw rnav::ConfigError("--threshold latitude/longitude out of range: '" + v + "'");
  return {x[0], x[1], x[2]};
}

}  // namespace

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_import_adsb", [&]() -> int {
    std::string file;
    rnav::GlitchOptions g;
    rnav::ApproachSearchOptions a;
    std::string scenario, out, thr, heading;
    bool list = false, force = false;
    long approach = 0;
    rnav::ReplayExportOptions ex;
    auto num = [](const char* opt, double& x) { return [opt, &x](const std::string& v) { x = number(opt, v); }; };
    rnav::cli::Parser p(
        "rnav_import_adsb",
        "FILE --list [options]\n"
        "FILE --approach N --out FILE.csv [--lead-s S] [--end-x-m X] [--force] [options]",
        "An ADS-B flight (JSON or JSON.gz records, sim/trajectory/adsb_records.hpp): --list prints the approaches "
        "it flies towards the runway; --approach N writes the N-th as a replay CSV (t_s, lat_deg, lon_deg, h_m) "
        "for the scenario key trajectory.replay_csv. Records failing the glitch rules are removed first (their "
        "counts per rule go to stderr).");
    p.positionals("FILE", "the ADS-B flight's records (JSON or JSON.gz)", [&](const std::string& v) {
      if (!file.empty()) throw rnav::ConfigError("unexpected argument '" + v + "' (FILE already given)");
      file = v;
    });
    p.flag("--list", "print the approaches found and exit", list)
        .value("--approach", "N", "export the N-th approach of --list, N >= 1", "none",
               [&](const std::string& v) { approach = static_cast<long>(rnav::parse_integer("--approach", v, 1, 1000000)); })
        .value("--out", "FILE.csv",
               "with --approach: the replay CSV to write, and FILE.units.json beside it (each column's unit and meaning)",
               "required with --approach", out)
        .flag("--force", "replace an existing --out file (without it, an existing file is an error)", force)
        .value("--lead-s", "S", "also write the S seconds [s] of flight before the approach, >= 0", "0 s", num("--lead-s", ex.lead_s))
        .value("--end-x-m", "X",
               "stop the export before the first point with x < X [m] in the landing frame (e.g. 0: at the threshold)",
               "at the approach's lowest point", num("--end-x-m", ex.end_x_m))
        .value("--scenario", "FILE", "take the runway (runway.threshold_*, runway.heading_deg) from a scenario file",
               "our scenario's LOWW 29", scenario)
        .value("--threshold", "LAT,LON,H_M", "runway threshold: latitude [deg], longitude [deg], height above WGS84 [m]",
               "48.10153,16.58495,228", thr)
        .value("--heading-deg", "H", "landing true heading [deg]", "295.9 deg", heading)
        .value("--height-source", "baro|geo",
               "barometric altitude (in every file) or geoaltitude (GNSS); baro altitude is not ellipsoidal height",
               "baro", [&](const std::string& v) {
                 if (v != "baro" && v != "geo") throw rnav::ConfigError("--height-source must be baro or geo, got '" + v + "'");
                 g.height = a.height = v == "baro" ? rnav::HeightSource::baro : rnav::HeightSource::geo;
               })
        .value("--height-offset-m", "M", "h_m = height_ft * 0.3048 + M [m]",
               "fitted per approach so its glide path crosses the threshold at --glide-path-tch-m",
               [&](const std::string& v) { a.height_offset_m = number("--height-offset-m", v); })
        .value("--glide-path-tch-m", "M", "height [m] of the fitted glide path over the threshold", "15 m",
               num("--glide-path-tch-m", a.glide_path_tch_m))
        .value("--max-speed-kt", "KT", "glitch rule: highest plausible ground speed [kt]", "400 kt", num("--max-speed-kt", g.max_speed_kt))
        .value("--max-vertical-rate-fpm", "FPM", "glitch rule: highest plausible vertical rate [ft/min]", "6000 ft/min",
               num("--max-vertical-rate-fpm", g.max_vertical_rate_fpm))
        .value("--altitude-tolerance-ft", "FT", "glitch rule: altitude allowance independent of the time step [ft]", "300 ft",
               num("--altitude-tolerance-ft", g.altitude_tolerance_ft))
        .value("--max-reject-run-s", "S", "glitch rule: longest run of removals trusted [s]", "60 s",
               num("--max-reject-run-s", g.max_reject_run_s))
        .value("--course-tolerance-deg", "D", "approach search: on-course half-width [deg]", "15 deg",
               num("--course-tolerance-deg", a.course_tolerance_deg))
        .value("--min-descent-m", "M", "approach search: least descent to the lowest point [m]", "150 m",
               num("--min-descent-m", a.min_descent_m))
        .value("--min-duration-s", "S", "approach search: least duration of an approach [s]", "60 s",
               num("--min-duration-s", a.min_duration_s))
        .value("--max-gap-s", "S", "approach search: a longer time step [s] between kept points ends a run", "30 s",
               num("--max-gap-s", a.max_gap_s))
        .epilog("Exit status: 0 ok, 2 bad input, 1 other failure.");
    if (!p.parse(argc, argv, std::cout)) return 0;
    if (file.empty()) throw rnav::ConfigError("FILE is required (see rnav_import_adsb --help)");
    if (list == (approach > 0)) throw rnav::ConfigError("give exactly one of --list and --approach N");
    if (approach > 0 && out.empty()) throw rnav::ConfigError("--approach needs --out FILE.csv");
    if (!out.empty() && !force && std::filesystem::exists(std::filesystem::symlink_status(out)))
      throw rnav::ConfigError("--out " + out + " exists; pass --force to replace it");
    if (ex.lead_s < 0) throw rnav::ConfigError("--lead-s must be >= 0");
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
      throw rnav::ConfigError("--approach " + std::to_string(approach) + ": only " +
                              std::to_string(found.size()) + " approach(es) found (see --list)");
    const auto& ap = found[static_cast<std::size_t>(approach - 1)];
    const std::size_t rows = rnav::write_replay_csv(out, clean.kept, ap, a, ex);
    std::cerr << "import: approach " << approach << " (" << ap.t_end_s - ap.t_start_s << " s, "
              << ap.dist_start_m << " m -> " << ap.dist_end_m << " m from the threshold, height offset "
              << ap.offset_m << " m) with " << ex.lead_s << " s lead, ending before x = " << ex.end_x_m << " m: " << rows << " rows -> " << out << "\n";
    return 0;
  });
}
