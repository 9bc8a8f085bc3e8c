#include "sim/target/target_options.hpp"

namespace rnav {

void check_target(const TargetOptions& o) {
  for (const auto& m : o.manoeuvres)
    if (m[0] < 0 || m[1] <= 0)
      throw ConfigError("scenario key 'target.manoeuvres': each needs t_s >= 0 and duration_s > 0");
}

}  // namespace rnav
