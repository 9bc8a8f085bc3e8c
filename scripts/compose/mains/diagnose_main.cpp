// rnav_diagnose prl|uav|multi INPUT [options] (one option table below; --help prints it).
// INPUT: a CSV folder (README, "Measured data") or an LCM event log of a simulation run
// (scripts/run --lcm-log FILE, lcm-logger): one realization (--realization, default 0), its
// streams checked for loss and order; the site from --scenario (with --set) or else from the
// log's SIM_SCENARIO. Prints the report; writes JSON.
#include "common/io/atomic_file.hpp"
#include "common/io/cli.hpp"
#include "common/io/process_memory.hpp"
#include "common/io/csv_table.hpp"
#include "common/io/did_you_mean.hpp"
#include "common/io/config.hpp"
#include "estimators/diagnosis/io/lcm_log_input.hpp"
#include "estimators/diagnosis/io/lcm_log_streams.hpp"
#include "estimators/diagnosis/multi_diagnose.hpp"
#include "estimators/diagnosis/prl_diagnose.hpp"
#include "estimators/diagnosis/uav_diagnose.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

namespace {

constexpr int kReportInjections = 20;  // injections per check batch of a report's limits

// The most data rows diagnosed: the diagnosis's time and memory grow with them (a landing
// flight with --injections 0: about 1 ms and 15 kB per plot; a multi-sensor recording of
// 39 000 detection rows, 24 s and 220 MB; the nine Autoferry recordings pooled, 72 793 rows,
// about a minute), the CSV limit (--max-input-mb) bounds only the reading. 0: the kind's default.
constexpr long long kDefaultMaxRows = 50000, kDefaultMaxRowsMulti = 150000;

constexpr double kBig = std::numeric_limits<double>::max();

// What the command line sets: KIND and the INPUTs, the outputs, each kind's options.
struct Options {
  std::vector<std::string> pos;
  std::string json, residuals;
  std::string apply;  // --apply FILE: multi, a calibration checked instead of a diagnosis
  rnav::DiagnoseOptions o;
  rnav::UavDiagnoseOptions uo;
  rnav::MultiDiagnoseOptions mo;
  rnav::LcmLogOptions lo;
  bool log_options = false;
  long long max_rows = 0;  // --max-rows; 0: the kind's default
};

// A CSV folder, an LCM event log, or an error naming INPUT.
bool is_log_input(const std::string& input) {
  namespace fs = std::filesystem;
  if (fs::is_directory(input)) return false;
  if (!fs::exists(input)) throw rnav::ConfigError("INPUT '" + input + "': no such file or directory");
  if (!fs::is_regular_file(input) || !rnav::is_lcm_log(input))
    throw rnav::ConfigError("INPUT '" + input +
                            "' is neither a CSV folder nor an LCM event log (no LCM sync word 0xEDA1DA01 at its start)");
  return true;
}

// The report's defaults where they differ from the library's: limits by injection, candidates
// tested two at once (--threads' default, as the injections), and progress lines on stderr.
void set_report_defaults(Options& a) {
  a.o.search.threads = a.uo.search.threads = a.mo.search.threads = a.o.search.injection.threads;
  // Every prl and uav report states limits measured by injection (the library's default is the
  // Fisher limits alone, for callers that run many searches); multi-sensor problems are larger
  // and their catalogues long: Fisher unless asked.
  a.o.search.injection.injections = a.uo.search.injection.injections = kReportInjections;
  a.o.search.injection.progress = a.uo.search.injection.progress = a.mo.search.injection.progress = [](const std::string& line) {
    std::cerr << "diagnose: limit by injection: " << line << std::endl;
  };
  // Where a long search is: a line at most every 2 s once it has run 3 s (a 20 Hz flight of
  // 9 205 plots takes 9 s with --injections 0, the default limits by injection minutes), with the wall time since the start.
  struct Progress {
    std::mutex m;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last = start;
  };
  auto progress = std::make_shared<Progress>();
  a.o.search.progress = a.uo.search.progress = a.mo.search.progress = [progress](const std::string& line) {
    constexpr double kQuietS = 3, kEveryS = 2;
    const std::lock_guard<std::mutex> lock(progress->m);
    const auto now = std::chrono::steady_clock::now();
    const double since_start = std::chrono::duration<double>(now - progress->start).count();
    if (since_start < kQuietS || std::chrono::duration<double>(now - progress->last).count() < kEveryS) return;
    progress->last = now;
    char t[32];
    std::snprintf(t, sizeof t, "%.0f s", since_start);
    std::cerr << "diagnose: " << t << ": " << line << std::endl;
  };
}

// Sets a to the option's value, a number.
auto num(const char* opt, double& a) {
  return [opt, &a](const std::string& v) { a = rnav::cli::number(opt, v, -kBig, kBig); };
}

// Sets a, b and c to the option's value, a number.
auto num_all(const char* opt, double& a, double& b, double& c) {
  return [opt, &a, &b, &c](const std::string& v) { a = b = c = rnav::cli::number(opt, v, -kBig, kBig); };
}

// Sets a and b to the option's value, a number.
auto num_two(const char* opt, double& a, double& b) {
  return [opt, &a, &b](const std::string& v) { a = b = rnav::cli::number(opt, v, -kBig, kBig); };
}

// The options of the outputs and of the input's size.
void add_output_options(rnav::cli::Parser& p, Options& a) {
  p.value("--json", "FILE", "write the report as JSON to FILE", "none", a.json)
      .value("--max-input-mb", "M",
             "the largest CSV input file read [MB]; a larger one is refused up front, naming its size, > 0",
             "67.1 MB (64 MiB)", [](const std::string& v) {
               const double mb = rnav::cli::number("--max-input-mb", v, 1e-6, 1e6);
               rnav::set_max_csv_bytes(static_cast<std::uint64_t>(mb * 1e6));
             })
      .value("--max-rows", "N",
             "the most data rows diagnosed (radar plots, bearings, or detections over all recordings); more are "
             "refused before the diagnosis, naming the count (a landing flight with --injections 0 takes about "
             "1 ms and 15 kB per plot), >= 1",
             std::to_string(kDefaultMaxRows) + " for prl and uav, " + std::to_string(kDefaultMaxRowsMulti) + " for multi",
             [&a](const std::string& v) {
               a.max_rows = rnav::parse_integer("--max-rows", v, 1, std::numeric_limits<long long>::max());
             })
      .value("--residuals", "FILE",
             "write the residuals (per plot or frame, nominal and extended model) as CSV to FILE, and each column's "
             "unit and meaning beside it (FILE without .csv + .units.json)",
             "none", a.residuals);
}

// The options of the effect search, common to every kind.
void add_search_options(rnav::cli::Parser& p, Options& a) {
  auto& o = a.o;
  auto& uo = a.uo;
  auto& mo = a.mo;
  p.value("--alpha", "A", "familywise false-alarm level, (0, 0.5)", "0.01",
          num_all("--alpha", o.search.alpha, uo.search.alpha, mo.search.alpha))
      .value("--noise-set-q", "Q",
             "an effect stays named only if its 2 log LR, least over each channel's noise models within Q / 2 of "
             "the best REML log-likelihood, still passes; 0: the plug-in noise estimate only",
             "4", num_all("--noise-set-q", o.search.noise_set_q, uo.search.noise_set_q, mo.search.noise_set_q))
      .value("--injections", "N",
             "limits measured by injection: N injections in each check batch at a fitted 90 % size (after a "
             "ladder of 10 per size from the Fisher limit up or down); 0: Fisher limits only, >= 0",
             "20 for prl and uav, 0 for multi", [&o, &uo, &mo](const std::string& v) {
               const int n = static_cast<int>(rnav::parse_integer("--injections", v, 0, 100000));
               o.search.injection.injections = uo.search.injection.injections = mo.search.injection.injections = n;
             })
      .value("--limits-for", "LIST",
             "measure the injected limits of these entries only (comma-separated: name, name@scope, or either "
             "with :param, e.g. time_offset,bias_step:glide_rad)", "every entry", [&o, &uo, &mo](const std::string& v) {
               std::vector<std::string> list;
               std::stringstream ss(v);
               for (std::string x; std::getline(ss, x, ',');)
                 if (!x.empty()) list.push_back(x);
               if (list.empty()) throw rnav::ConfigError("--limits-for: no entry named in '" + v + "'");
               o.search.injection.entries = uo.search.injection.entries = mo.search.injection.entries = list;
             })
      .value("--threads", "N", "concurrent work: candidate effects tested at once, injected searches (multi: also target tracks searched at once, and recordings left out at once), >= 1", "2", [&o, &uo, &mo](const std::string& v) {
               const int n = static_cast<int>(rnav::parse_integer("--threads", v, 1, 256));
               o.search.injection.threads = uo.search.injection.threads = mo.search.injection.threads = n;
               o.search.threads = uo.search.threads = mo.search.threads = n;
             })
      .value("--injection-seed", "N", "seed of the injections' noise, >= 0", "1", [&o, &uo, &mo](const std::string& v) {
               const auto n = static_cast<std::uint64_t>(rnav::parse_integer("--injection-seed", v, 0, std::numeric_limits<long long>::max()));
               o.search.injection.seed = uo.search.injection.seed = mo.search.injection.seed = n;
             })
      .value("--null-set-q", "Q",
             "a scanned effect's (step, period) test: the null's noise ranges over the models within Q / 2 of "
             "the best REML log-likelihood with the effect in the model; 0: over every noise model (the profile "
             "likelihood ratio)", "5 for prl and uav, 9 for multi", num_all("--null-set-q", o.search.null_set_q, uo.search.null_set_q, mo.search.null_set_q))
      .value("--confound-corr", "C", "canonical correlation above which two effects are reported as confounded, (0, 1)",
             "0.9", num_all("--confound-corr", o.search.confound_corr, uo.search.confound_corr, mo.search.confound_corr));
}

// The options of one kind or two: prl, uav, multi.
void add_kind_options(rnav::cli::Parser& p, Options& a) {
  auto& o = a.o;
  auto& uo = a.uo;
  auto& mo = a.mo;
  p.value("--split-time", "S", "prl: fit on t < S [s], score the gain after it", "400 s, the paper's switch",
          num("--split-time", o.split_time_s))
      .value("--nav-sigma", "M", "prl: the nav solution's time-correlated position error per axis [m], 1 sigma", "1.9 m",
             num("--nav-sigma", o.nav_sigma_m))
      .value("--rate-window", "S",
             "prl: the nav velocity behind time_offset's columns is the slope of a line fitted to the nav "
             "positions within S seconds centred on each plot (0: the difference of the two around it), >= 0",
             "2 s", num("--rate-window", o.rate_window_s))
      .value("--nav-tau", "S", "prl: its correlation time [s]", "120 s", num("--nav-tau", o.nav_tau_s))
      .value("--gate-deg", "D", "uav, multi: association gate of bearings around the reference bearing [deg]",
             "4 deg for uav, 3 deg for multi", num_two("--gate-deg", uo.gate_deg, mo.association.gate_bearing_deg))
      .value("--gate-m", "M", "multi: association gate of range sensors around the reference position [m]", "20 m",
             num("--gate-m", mo.association.gate_position_m))
      .value("--reference-max-gap", "S",
             "multi: interpolate a target's reference track only between samples at most S apart [s] (AIS: 10 or "
             "more), > 0", "2 s", num("--reference-max-gap", mo.association.reference_max_gap_s))
      .value("--reference-accel", "A",
             "multi: RMS acceleration per axis of a target between its reference samples [m/s^2], behind the "
             "interpolation's own uncertainty in the noise (a b / 2 off the chord, b = (t - t_a)(t_b - t)); -1: each "
             "target's own from its reference's second differences; 0: the reference taken as exact",
             "-1", num("--reference-accel", mo.association.reference_accel_mps2))
      .value("--reference-jump-accel", "A",
             "multi: a reference sample further off the chord through its neighbours (0.25 s either side) than a "
             "target accelerating at A [m/s^2] could be, beyond the track's own scatter, is a jump of the reference "
             "(a GNSS fix changing): the reference is used only on its longest stretch without jumps (named in the "
             "report); 0: no check, >= 0", "5", num("--reference-jump-accel", mo.association.reference_jump_accel_mps2))
      .value("--sigma-deg", "D", "uav, multi: nominal bearing noise, 1 sigma [deg]", "0.5 deg",
             num_two("--sigma-deg", uo.sigma_deg, mo.sigma_bearing_deg))
      .value("--sigma-range-m", "M", "multi: nominal range noise of range sensors, 1 sigma [m]", "1 m",
             num("--sigma-range-m", mo.sigma_range_m))
      .value("--split-fraction", "F", "uav, multi: fit on the first fraction F of the span, score the rest, (0.2, 0.9)",
             "0.6", num_two("--split-fraction", uo.split_fraction, mo.split_fraction))
      .value("--apply", "FILE",
             "multi: no diagnosis; the hardware effects of FILE (a diagnosis JSON of other recordings, their values "
             "carried as the leave-one-out carries them, or {\"effects\": [{\"name\", \"scope\": {\"sensor\", "
             "\"target\"}, \"estimate\"}]} in the catalogue's units: s, rad, m) removed from each INPUT, and the error "
             "per sensor:target pair printed, nominal and calibrated (a calibration checked on new recordings); "
             "{\"calibrations\": [{\"effects\": [...]}, ...]}: several checked at once (a grid), one line each",
             "none", [&a](const std::string& v) { a.apply = v; })
      .value("--carry-tolerance", "T",
             "multi: a fit's hardware values are carried to another recording (each recording left out, and "
             "--apply of the JSON) at the shares of their fitted values, on a grid in [0, 1], with the lowest error on "
             "the recordings they were fitted on that leave none of those recordings' sensor:target pairs worse than T x "
             "nominal (1: do no harm where fitted); 0: whole, >= 1 or 0", "1",
             num("--carry-tolerance", mo.carry.tolerance))
      .value("--carry-alpha", "A",
             "multi with several INPUTs: the familywise level of the fits whose hardware is carried (each recording left "
             "out, and the JSON's carry that --apply uses); the causes named stay at --alpha, (0, 0.5)", "0.1",
             num("--carry-alpha", mo.carry_alpha))
      .value("--max-hull-m", "L,B",
             "multi: a target without a size on record (targets.csv: target,length_m,beam_m) is at most L m long and B m "
             "wide; an antenna or hull offset beyond its hull is refused as an explanation (a sign of wrong association), "
             "each > 0", "400,62 (the largest ships afloat)",
             [&mo](const std::string& v) {
               const auto c = v.find(',');
               if (c == std::string::npos) throw rnav::ConfigError("--max-hull-m: expected L,B (metres), got '" + v + "'");
               mo.max_hull_length_m = rnav::cli::number("--max-hull-m", v.substr(0, c), 1e-3, 1e4);
               mo.max_hull_beam_m = rnav::cli::number("--max-hull-m", v.substr(c + 1), 1e-3, 1e4);
             })
      .flag("--no-leave-one-out", "multi with several INPUTs: skip scoring each recording with the model fitted on the others",
            [&mo] { mo.leave_one_out = false; })
      .flag("--ignore-truth", "uav: diagnose on a track fitted to the bearings; truth only scores the gain",
            uo.ignore_truth)
      .flag("--keep-references", "uav: diagnose even where truth.csv's target does not fit the bearings as stamped (a "
            "second object that follows the target's path looks like a time shift of its reference)",
            [&uo] { uo.check_references = false; })
      .value("--seed", "N", "uav: seed of that track fit's initialisation, >= 0", "1",
             [&uo](const std::string& v) { uo.seed = static_cast<std::uint64_t>(rnav::parse_integer("--seed", v, 0, std::numeric_limits<long long>::max())); });
}

// The options of an LCM event log as INPUT.
void add_log_options(rnav::cli::Parser& p, Options& a) {
  p.value("--realization", "R", "LCM log: which realization to diagnose, >= 0", "0",
          [&a](const std::string& v) {
            a.lo.realization = static_cast<int>(rnav::parse_integer("--realization", v, 0, 1000000000));
            a.log_options = true;
          })
      .value("--scenario", "FILE", "LCM log: the scenario giving the radar's site and sim time 0",
             "the scenario the log carries on SIM_SCENARIO", [&a](const std::string& v) {
               a.lo.scenario_file = v;
               a.log_options = true;
             })
      .repeated("--set", "key=value", "LCM log: override a key of that scenario",
             [&a](const std::string& v) {
               a.lo.overrides.push_back(v);
               a.log_options = true;
             });
}

// The option table of rnav_diagnose (--help prints it in this order), setting a.
rnav::cli::Parser make_parser(Options& a) {
  rnav::cli::Parser p(
      "rnav_diagnose", "prl|uav|multi INPUT [INPUT...] [options]",
      "Shows what the nominal (paper's) model gets wrong in measured data: fits it to the residuals, names "
      "the effects of the catalogue the data support (estimate +- standard error, evidence), says which "
      "ones the geometry cannot tell apart, and measures the extended model's gain out of sample. Prints "
      "the report; --json writes it as JSON. scripts/diagnose adds plots.");
  p.positionals("KIND INPUT [INPUT...]",
                "KIND: prl (landing radar), uav (azimuth-only) or multi (multi-sensor, multi-target). INPUT: a CSV "
                "folder (docs/diagnosis.md, 'Measured data'), or for prl and uav an LCM event log of a simulation run "
                "(scripts/run --lcm-log FILE); multi takes several folders, diagnosed together (each named by "
                "its folder's name: hardware effects one value in all, validated by leaving each out)",
                [&a](const std::string& v) { a.pos.push_back(v); });
  add_output_options(p, a);
  add_search_options(p, a);
  add_kind_options(p, a);
  add_log_options(p, a);
  p.epilog("Units: the text report shows angles in degrees, as the CSV inputs and the options give them "
           "(parameters and units named deg, X_deg, X_degps), every other value in the unit its name ends "
           "with (_m, _s, _mps); the JSON report keeps radians (rad, X_rad). Exit status: 0 ok, 2 bad "
           "input, 1 other failure.");
  return p;
}

// rows: the data's count of `what`, refused beyond --max-rows
void check_rows(const Options& a, std::size_t rows, const std::string& what, const std::string& where) {
  if (static_cast<long long>(rows) > a.max_rows)
    throw rnav::ConfigError(where + ": " + std::to_string(rows) + " " + what + ", more than the " +
                            std::to_string(a.max_rows) + " diagnosed at most (--max-rows N raises it; the time and "
                            "memory of the diagnosis grow with them)");
}

// Writes the report as JSON to --json FILE, if given.
void write_json(const Options& a, const nlohmann::ordered_json& j) {
  if (a.json.empty()) return;
  rnav::write_file_atomic(a.json, j.dump(2) + "\n");
}

// KIND multi: the INPUT folders read, diagnosed together, the report printed and written.
int run_multi(const Options& a) {
  const auto& pos = a.pos;
  std::vector<std::pair<std::string, rnav::MultiSensorData>> recs;
  for (std::size_t k = 1; k < pos.size(); ++k) {
    const std::string& in = pos[k];
    if (a.log_options || !std::filesystem::is_directory(in))
      throw rnav::ConfigError("KIND multi: INPUT must be a multi-sensor CSV folder ('" + in + "' is not a folder, or LCM-log options were given)");
    std::filesystem::path dir = std::filesystem::absolute(in).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();  // "out/af4/"
    const std::string name = dir.filename().string();
    for (const auto& r : recs)
      if (r.first == name) throw rnav::ConfigError("KIND multi: two INPUT folders are both named '" + name + "' (recordings are named by their folder)");
    recs.push_back({name, rnav::MultiSensorData::read_folder(in)});
  }
  std::size_t rows = 0;
  for (const auto& r : recs) rows += r.second.detections.size();
  check_rows(a, rows, "detection rows", recs.size() == 1 ? pos[1] : std::to_string(recs.size()) + " recordings");
  if (!a.apply.empty()) {
    if (!a.residuals.empty()) throw rnav::ConfigError("--apply checks a calibration: it writes no --residuals");
    rnav::require_regular_file(a.apply);
    std::ifstream in(a.apply);
    if (!in) throw rnav::ConfigError("--apply: cannot open '" + a.apply + "'");
    const auto doc = rnav::parse_json_checked(in, "calibration file '" + a.apply + "'", /*allow_comments=*/true);
    const std::vector<rnav::Calibration> cals = rnav::read_calibrations(doc, "calibration file '" + a.apply + "'");
    std::vector<std::vector<rnav::AppliedEffect>> effects;
    for (const auto& c : cals) effects.push_back(c.effects);
    rnav::CalibrationBatch batch{a.apply, rnav::check_calibrations(recs, effects, a.mo)};
    for (std::size_t c = 0; c < cals.size(); ++c) {
      rnav::CalibrationReport& rep = batch.reports[c];
      rep.source = cals.size() == 1 ? a.apply : a.apply + " calibrations[" + std::to_string(c) + "]";
      rep.own = cals[c].own;
      rep.withheld = cals[c].withheld;
      rep.findings = cals[c].findings;
    }
    const bool one = doc.is_object() && !doc.contains("calibrations");
    std::cout << (one ? batch.reports.front().text() : batch.text());
    write_json(a, one ? batch.reports.front().to_json() : batch.to_json());
    return 0;
  }
  const auto rep = rnav::diagnose_multi_pooled(recs, a.mo);
  std::cout << rep.text();
  if (!a.residuals.empty()) rep.write_residuals_csv(a.residuals);
  write_json(a, rep.to_json());
  return 0;
}

// KIND prl or uav: INPUT (a CSV folder or an LCM event log) read and diagnosed, the report
// printed and written.
int run_single(const Options& a, const std::string& kind, const std::string& input) {
  const bool log = is_log_input(input);
  if (!log && a.log_options)
    throw rnav::ConfigError("--realization, --scenario and --set apply to an LCM event log; '" +
                            input + "' is a CSV folder");
  std::string summary;
  auto prl_data = [&] {
    auto d = log ? rnav::read_prl_lcm_log(input, a.lo, &summary) : rnav::PrlFlightData::read_folder(input);
    check_rows(a, d.plots.size(), "radar plots", input);
    return d;
  };
  auto uav_data = [&] {
    auto d = log ? rnav::read_uav_lcm_log(input, a.lo, &summary) : rnav::AzimuthData::read_folder(input);
    std::size_t n = 0;
    for (const auto& f : d.frames) n += f.bearings_rad.size();
    check_rows(a, n, "bearings", input);
    return d;
  };
  const auto rep = kind == "prl" ? rnav::diagnose_prl(prl_data(), a.o) : rnav::diagnose_uav(uav_data(), a.uo);
  if (!summary.empty()) std::cerr << "diagnose: " << summary << "\n";
  std::cout << rep.text();
  if (!a.residuals.empty()) rep.write_residuals_csv(a.residuals);
  write_json(a, rep.to_json());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  rnav::cli::keep_freed_memory();
  return rnav::cli::guarded_main("rnav_diagnose", [&]() -> int {
    Options a;
    set_report_defaults(a);
    rnav::cli::Parser p = make_parser(a);
    if (!p.parse(argc, argv, std::cout)) return 0;
    const auto& pos = a.pos;
    if (pos.size() < 2) throw rnav::ConfigError("KIND and INPUT are required (see rnav_diagnose --help)");
    const std::string kind = pos[0], input = pos[1];
    if (kind != "prl" && kind != "uav" && kind != "multi")
      throw rnav::ConfigError("KIND must be prl, uav or multi, got '" + kind + "'" +
                              rnav::did_you_mean(kind, {"prl", "uav", "multi"}));
    if (pos.size() > 2 && kind != "multi")
      throw rnav::ConfigError("unexpected argument '" + pos[2] + "' (KIND " + kind + " takes one INPUT; only multi takes several)");
    if (a.max_rows == 0) a.max_rows = kind == "multi" ? kDefaultMaxRowsMulti : kDefaultMaxRows;
    if (kind == "multi") return run_multi(a);
    return run_single(a, kind, input);
  });
}
