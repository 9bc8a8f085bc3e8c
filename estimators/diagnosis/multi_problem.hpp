// The multi-sensor diagnosis posed to the effect-search engine: channels, residuals, the
// catalogue with its scopes, covariates and scope questions (multi_diagnose.hpp lists them).
#pragma once

#include "effect_search.hpp"
#include "multi_association.hpp"

#include <vector>

namespace rnav {

struct MultiProblem {
  Problem problem;
  std::vector<long> bearing_obs, range_obs;  ///< per associated detection: its observation index (-1: none)
  double split_time_s = 0;
  std::vector<std::string> dropped_channels;  ///< "name (n detections)": fewer than 10, not used
};

/// @param nominal_sigma_bearing_rad, nominal_sigma_range_m  nominal white noise (> 0)
/// @param split_fraction  estimation window = first fraction of the data's span
/// @param step_grid  grid size of the scanned bias_step
MultiProblem build_multi_problem(const std::vector<AssociatedDetection>& a, double nominal_sigma_bearing_rad,
                                 double nominal_sigma_range_m, double split_fraction, int step_grid);

}  // namespace rnav
