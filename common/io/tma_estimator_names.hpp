// The names of the azimuth-only estimators, shared by the estimator node (tma.estimators) and
// the UAV's guidance (uav.guidance_estimator) that uses one of their estimates.
#pragma once

#include <string>
#include <vector>

namespace rnav {

/// Every estimator name: "ekf", "rpekf", "ml", "pf".
const std::vector<std::string>& tma_estimator_names();

}  // namespace rnav
