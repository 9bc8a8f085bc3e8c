// rnav_export_prl: simulate one landing-approach realization (optionally with hidden effects,
// prl_effects.*) and write it as a flight-test CSV folder for scripts/diagnose.
// Options: one table below (rnav_export_prl --help prints it).
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "common/io/config.hpp"
#include "scripts/compose/export/prl_export.hpp"

#include <iostream>
#include <limits>

int main(int argc, char** argv) {
  return rnav::cli::guarded_main("rnav_export_prl", [&]() -> int {
    std::string file, out;
    std::vector<std::string> overrides;
    int r = 0;
    bool force = false;
    std::int64_t seed = 1;
    rnav::cli::Parser p("rnav_export_prl", "--scenario FILE [--set key=value]... [--seed S] [--realization R] --out DIR [--force]",
                        "Simulates one landing-approach realization (with any hidden effects set by --set prl_effects.*) "
                        "and writes it as a flight-test CSV folder for scripts/diagnose prl: site.json, radar.csv "
                        "(t_s, range_m, azimuth_deg, elevation_deg), nav.csv and truth.csv (t_s, lat_deg, lon_deg, h_m), each CSV "
                        "with NAME.units.json beside it (each column's unit and meaning).");
    p.value("--scenario", "FILE", "landing-radar scenario JSON file (e.g. sim/scenarios/paper.json)", "required", file)
        .repeated("--set", "key=value", "override a scenario key, e.g. --set prl_effects.time_offset_s=0.4", overrides)
        .value("--seed", "S", "ensemble seed (an integer)", "1",
               [&](const std::string& v) {
                 seed = rnav::parse_integer("--seed", v, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
               })
        .value("--realization", "R", "which realization of that seed's ensemble, 0 ... 1e9", "0",
               [&](const std::string& v) { r = static_cast<int>(rnav::parse_integer("--realization", v, 0, 1000000000)); })
        .value("--out", "DIR", "output folder; it must be new, empty or an earlier output (its .rnav-output marker) unless --force",
               "required", out)
        .flag("--force", "write into --out DIR whatever it holds", force)
        .epilog("Scenario keys: see rnav_clock --scenario FILE --check (every key with its value) or the README.");
    if (!p.parse(argc, argv, std::cout)) return 0;
    rnav::cli::require("rnav_export_prl", {{"--scenario FILE", !file.empty()}, {"--out DIR", !out.empty()}});
    rnav::prepare_output_dir(out, force);
    const auto sc = rnav::Scenario::load(file, overrides);
    std::string failure;
    const int rc = rnav::export_prl_flight(sc, seed, r, out, &failure);
    if (rc != 0) {
      std::cerr << rnav::cli::error_line("rnav_export_prl", "failed: " + failure) << "\n";
      return rc;
    }
    return 0;
  });
}
