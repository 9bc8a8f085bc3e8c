// rnav_diagnose prl|uav INPUT [--json FILE] [--split-time S] [--alpha A] [...]
//               [--realization R] [--scenario FILE] [--set key=value]...
// INPUT: a CSV folder (README, "Measured data") or an LCM event log of a simulation run
// (scripts/run --lcm-log FILE, lcm-logger): one realization (--realization, default 0), its
// streams checked for loss and order; the site from --scenario (with --set) or else from the
// log's SIM_SCENARIO. Prints the report; writes JSON.
#include "atomic_file.hpp"
#include "config.hpp"
#include "lcm_log_input.hpp"
#include "lcm_log_streams.hpp"
#include "multi_diagnose.hpp"
#include "prl_diagnose.hpp"
#include "uav_diagnose.hpp"

#include <filesystem>
#include <fstream>
#include <cmath>
#include <iostream>

namespace {

const char* kUsage =
    "usage: rnav_diagnose prl|uav|multi INPUT [--json FILE] [--residuals FILE] [--split-time S] [--alpha A]\n"
    "         [--nav-sigma M] [--nav-tau S] [--confound-corr C] [--gate-deg D] [--sigma-deg D]\n"
    "         [--split-fraction F] [--ignore-truth] [--seed N] [--noise-set-q Q]\n"
    "         [--realization R] [--scenario FILE] [--set key=value]...\n"
    "  prl: --split-time (default 400 s), --nav-sigma (default 1.9 m), --nav-tau (default 120 s); uav: --gate-deg, --sigma-deg, --split-fraction,\n"
    "  --ignore-truth (diagnose on a track fitted to the bearings; truth only scores the gain),\n"
    "  --seed (of that fit's initialisation)\n"
    "  --noise-set-q: an effect stays named only if its 2 log LR, least over each channel's noise\n"
    "  models within Q / 2 of the best REML log-likelihood, still passes (default 4; 0: plug-in\n"
    "  noise estimate only)\n"
    "  multi: a multi-sensor folder (observer.csv, detections.csv, truth.csv); --gate-deg (bearing\n"
    "  gate, default 3), --gate-m (range sensors' position gate, default 20), --sigma-deg (nominal\n"
    "  bearing sigma, default 0.5), --sigma-range-m (default 1), --split-fraction (default 0.6)\n"
    "  INPUT: a CSV folder, or an LCM event log (scripts/run --lcm-log FILE); for a log,\n"
    "  --realization picks one (default 0) and --scenario/--set give the site (default: the\n"
    "  scenario the log carries on SIM_SCENARIO)";

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

int integer(const std::string& opt, const std::string& v) {
  std::size_t pos = 0;
  int x = 0;
  try {
    x = std::stoi(v, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (v.empty() || pos != v.size() || x < 0)
    throw rnav::ConfigError(opt + " '" + v + "' is not a non-negative integer");
  return x;
}

// A finite number, or an error naming the option.
double number(const std::string& opt, const std::string& v) {
  std::size_t pos = 0;
  double x = 0;
  try {
    x = std::stod(v, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (v.empty() || pos != v.size() || !std::isfinite(x)) throw rnav::ConfigError(opt + " '" + v + "' is not a finite number");
  return x;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3) throw rnav::ConfigError(kUsage);
    const std::string kind = argv[1], input = argv[2];
    if (kind != "prl" && kind != "uav" && kind != "multi")
      throw rnav::ConfigError("diagnose: kind must be prl, uav or multi, got '" + kind + "'");
    std::string json, residuals;
    rnav::DiagnoseOptions o;
    rnav::UavDiagnoseOptions uo;
    rnav::MultiDiagnoseOptions mo;
    rnav::LcmLogOptions lo;
    bool log_options = false;
    for (int i = 3; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw rnav::ConfigError("diagnose: option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--json") json = value();
      else if (a == "--split-time") o.split_time_s = number(a, value());
      else if (a == "--alpha") o.search.alpha = uo.search.alpha = mo.search.alpha = number(a, value());
      else if (a == "--gate-deg") uo.gate_deg = mo.association.gate_bearing_deg = number(a, value());
      else if (a == "--gate-m") mo.association.gate_position_m = number(a, value());
      else if (a == "--sigma-deg") uo.sigma_deg = mo.sigma_bearing_deg = number(a, value());
      else if (a == "--sigma-range-m") mo.sigma_range_m = number(a, value());
      else if (a == "--residuals") residuals = value();
      else if (a == "--noise-set-q") o.search.noise_set_q = uo.search.noise_set_q = mo.search.noise_set_q = number(a, value());
      else if (a == "--confound-corr") o.search.confound_corr = uo.search.confound_corr = mo.search.confound_corr = number(a, value());
      else if (a == "--split-fraction") uo.split_fraction = mo.split_fraction = number(a, value());
      else if (a == "--ignore-truth") uo.ignore_truth = true;
      else if (a == "--seed") uo.seed = static_cast<std::uint64_t>(integer(a, value()));
      else if (a == "--nav-sigma") o.nav_sigma_m = number(a, value());
      else if (a == "--nav-tau") o.nav_tau_s = number(a, value());
      else if (a == "--realization") lo.realization = integer(a, value()), log_options = true;
      else if (a == "--scenario") lo.scenario_file = value(), log_options = true;
      else if (a == "--set") lo.overrides.push_back(value()), log_options = true;
      else throw rnav::ConfigError("diagnose: unknown option " + a);
    }
    auto write_json = [&](const nlohmann::ordered_json& j) {
      if (json.empty()) return;
      rnav::write_file_atomic(json, j.dump(2) + "\n");
    };
    if (kind == "multi") {
      if (log_options || !std::filesystem::is_directory(input))
        throw rnav::ConfigError("multi: INPUT must be a multi-sensor CSV folder ('" + input + "' is not a folder, or LCM-log options were given)");
      const auto rep = rnav::diagnose_multi(rnav::MultiSensorData::read_folder(input), mo);
      std::cout << rep.text();
      if (!residuals.empty()) rep.write_residuals_csv(residuals);
      write_json(rep.to_json());
      return 0;
    }
    const bool log = is_log_input(input);
    if (!log && log_options)
      throw rnav::ConfigError("--realization, --scenario and --set apply to an LCM event log; '" +
                              input + "' is a CSV folder");
    std::string summary;
    const auto rep =
        kind == "prl"
            ? rnav::diagnose_prl(log ? rnav::read_prl_lcm_log(input, lo, &summary) : rnav::PrlFlightData::read_folder(input), o)
            : rnav::diagnose_uav(log ? rnav::read_uav_lcm_log(input, lo, &summary) : rnav::AzimuthData::read_folder(input), uo);
    if (!summary.empty()) std::cerr << "diagnose: " << summary << "\n";
    std::cout << rep.text();
    if (!residuals.empty()) rep.write_residuals_csv(residuals);
    write_json(rep.to_json());
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "diagnose: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "diagnose: error: " << e.what() << "\n";
    return 1;
  }
}
