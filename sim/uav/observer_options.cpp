#include "sim/uav/observer_options.hpp"

#include <cmath>

namespace rnav {

double orbit_period_s(const ObserverOptions& o) { return 2 * M_PI * o.radius_m / o.speed_mps; }

}  // namespace rnav
