// One sensor frame through every azimuth-only estimator, with no transport: the UAV's nav state
// at the frame's time and the bearings detected in that frame (possibly none). Shared by the
// lock-step node (uav_tma_node) and the free-running node (uav_tma_free_node).
#pragma once

#include "estimators/uav_tma/tma_estimators.hpp"

#include <rnav/bearing_t.hpp>
#include <rnav/observer_state_t.hpp>
#include <rnav/tma_estimate_t.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace rnav {

/// Update (or predict, without bearings) every estimator to the frame at o.utime and append
/// each initialised estimator's estimate to `out` (estimators in their fixed order).
/// @param epoch_utime [us] sim time 0; every bearing's utime equals o.utime.
void process_tma_frame(std::vector<std::unique_ptr<tma::TmaEstimator>>& est, std::int64_t epoch_utime,
                       const observer_state_t& o, const std::vector<const bearing_t*>& bearings,
                       std::vector<tma_estimate_t>& out);

}  // namespace rnav
