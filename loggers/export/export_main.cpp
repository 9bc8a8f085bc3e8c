// rnav_export_prl: simulate one landing-approach realization (optionally with hidden effects,
// prl_effects.*) and write it as a flight-test CSV folder for scripts/diagnose.
// Usage: rnav_export_prl --scenario FILE [--set k=v]... [--seed S] [--realization R] --out DIR [--force]
// DIR must be new, empty or an earlier output (its .rnav-output marker); --force writes into any.
#include "atomic_file.hpp"
#include "config.hpp"
#include "prl_export.hpp"

#include <iostream>
#include <limits>

int main(int argc, char** argv) {
  try {
    std::string file, out;
    std::vector<std::string> overrides;
    int r = 0;
    bool force = false;
    std::int64_t seed = 1;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw rnav::ConfigError("export: option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--scenario") file = value();
      else if (a == "--set") overrides.push_back(value());
      else if (a == "--seed") seed = rnav::parse_integer(a, value(), std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
      else if (a == "--realization") r = static_cast<int>(rnav::parse_integer(a, value(), 0, 1000000000));
      else if (a == "--out") out = value();
      else if (a == "--force") force = true;
      else throw rnav::ConfigError("export: unknown option " + a);
    }
    if (file.empty() || out.empty()) throw rnav::ConfigError("export: --scenario and --out are required");
    rnav::prepare_output_dir(out, force);
    const auto sc = rnav::Scenario::load(file, overrides);
    std::string failure;
    const int rc = rnav::export_prl_flight(sc, seed, r, out, &failure);
    if (rc != 0) {
      std::cerr << "export: failed: " << failure << "\n";
      return rc;
    }
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "export: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "export: error: " << e.what() << "\n";
    return 1;
  }
}
