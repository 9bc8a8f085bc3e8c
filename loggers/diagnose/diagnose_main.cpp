// rnav_diagnose prl|uav INPUT [--json FILE] [--split-time S] [--alpha A]
// INPUT: a flight-test CSV folder (README, "Measured data"). Prints the report; writes JSON.
#include "config.hpp"
#include "prl_diagnose.hpp"
#include "uav_diagnose.hpp"

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  try {
    if (argc < 3) throw rnav::ConfigError("usage: rnav_diagnose prl INPUT [--json FILE] [--split-time S] [--alpha A]");
    const std::string kind = argv[1], input = argv[2];
    if (kind != "prl" && kind != "uav") throw rnav::ConfigError("diagnose: kind must be prl or uav, got '" + kind + "'");
    std::string json, residuals;
    rnav::DiagnoseOptions o;
    rnav::UavDiagnoseOptions uo;
    for (int i = 3; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw rnav::ConfigError("diagnose: option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--json") json = value();
      else if (a == "--split-time") o.split_time_s = std::stod(value());
      else if (a == "--alpha") o.alpha = uo.alpha = std::stod(value());
      else if (a == "--gate-deg") uo.gate_deg = std::stod(value());
      else if (a == "--sigma-deg") uo.sigma_deg = std::stod(value());
      else if (a == "--residuals") residuals = value();
      else if (a == "--confound-corr") o.confound_corr = std::stod(value());
      else if (a == "--nav-sigma") o.nav_sigma_m = std::stod(value());
      else if (a == "--nav-tau") o.nav_tau_s = std::stod(value());
      else throw rnav::ConfigError("diagnose: unknown option " + a);
    }
    const auto rep = kind == "prl" ? rnav::diagnose_prl(rnav::PrlFlightData::read_folder(input), o)
                                   : rnav::diagnose_uav(rnav::AzimuthData::read_folder(input), uo);
    std::cout << rep.text();
    if (!residuals.empty()) rep.write_residuals_csv(residuals);
    if (!json.empty()) {
      std::ofstream f(json + ".partial");
      f << rep.to_json().dump(2) << "\n";
      f.close();
      if (!f || std::rename((json + ".partial").c_str(), json.c_str()) != 0)
        throw std::runtime_error("cannot write " + json);
    }
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "diagnose: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "diagnose: error: " << e.what() << "\n";
    return 1;
  }
}
