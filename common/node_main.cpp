#include "node_main.hpp"

#include "lcm_bus.hpp"

#include <chrono>
#include <iostream>

namespace rnav {

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

int run_node_main(int argc, char** argv, const std::string& name,
                  const std::function<std::unique_ptr<LockstepNode>(Bus&, const Scenario&,
                                                                    const NodeArgs&)>& make) {
  try {
    NodeArgs args;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw ConfigError(name + ": option " + a + " needs a value");
        return argv[++i];
      };
      if (a == "--scenario") args.scenario_file = value();
      else if (a == "--set") args.overrides.push_back(value());
      else if (a == "--drop") args.drops.push_back(DropSpec::parse(value()));
      else if (a == "--lcm-url") args.lcm_url = value();
      else if (a == "--out") args.out_dir = value();
      else args.extra.push_back(a);
    }
    if (args.scenario_file.empty()) throw ConfigError(name + ": --scenario FILE is required");
    const Scenario sc = Scenario::load(args.scenario_file, args.overrides);
    std::cerr << name << ": options\n";
    sc.print(std::cerr);
    LcmBus bus(args.lcm_url);
    auto node = make(bus, sc, args);
    for (const auto& d : args.drops) node->add_drop(d);
    while (!node->done()) {
      bus.handle(20);
      node->poll(wall_seconds());
    }
    std::cerr << name << ": " << (node->exit_code() == 0 ? "finished" : "aborted by the clock")
              << "\n";
    return node->exit_code();
  } catch (const ConfigError& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace rnav
