#include "node_main.hpp"

#include <chrono>

namespace rnav {

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace rnav
