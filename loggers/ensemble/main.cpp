// rnav_inproc: the landing-approach ensemble in one process (same nodes, InprocBus).
// Usage: rnav_inproc --scenario FILE [--set k=v]... --realizations N --seed S --out DIR [--force]
// DIR must be new, empty or an earlier output (its .rnav-output marker); --force writes into any.
#include "atomic_file.hpp"
#include "inproc_ensemble.hpp"
#include "node_main.hpp"

#include <iostream>
#include <limits>

int main(int argc, char** argv) {
  try {
    std::string file, out;
    std::vector<std::string> overrides, drops;
    bool force = false;
    int n = 1;
    std::int64_t seed = 1;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--force") {
        force = true;
        continue;
      }
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw rnav::ConfigError("inproc: option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--scenario") file = value();
      else if (a == "--set") overrides.push_back(value());
      else if (a == "--realizations") n = static_cast<int>(rnav::parse_integer(a, value(), 1, 1000000000));
      else if (a == "--seed") seed = rnav::parse_integer(a, value(), std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
      else if (a == "--out") out = value();
      else if (a == "--drop") drops.push_back(value());
      else throw rnav::ConfigError("inproc: unknown option " + a);
    }
    if (file.empty()) throw rnav::ConfigError("inproc: --scenario FILE is required");
    if (!out.empty()) rnav::prepare_output_dir(out, force);
    const double t0 = rnav::wall_seconds();
    const auto r = rnav::scenario_kind(file) == "uav"
                       ? rnav::run_inproc_ensemble(rnav::UavScenario::load(file, overrides), n, seed, out, drops)
                       : rnav::run_inproc_ensemble(rnav::Scenario::load(file, overrides), n, seed, out, drops);
    if (r.exit_code != 0) {
      std::cerr << "inproc: run failed: " << r.failure << "\n";
      return r.exit_code;
    }
    std::cerr << "inproc: " << n << " realizations in " << rnav::wall_seconds() - t0 << " s, "
              << r.retries << " repeated\n";
    return 0;
  } catch (const rnav::ConfigError& e) {
    std::cerr << "inproc: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "inproc: error: " << e.what() << "\n";
    return 1;
  }
}
