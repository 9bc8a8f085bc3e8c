// Internal to the effect search: everything reported once the effects are chosen (estimates,
// evidence, confounding, detection limits, noise findings, out-of-sample gain, unexplained
// structure, scope answers).
#pragma once

#include "estimators/model_id/search_design.hpp"

namespace rnav::search_detail {

/// chosen: (catalogue entry, grid point) per effect; kept_lr: the 2 log LR each was kept with.
void report(const Design& d, const SearchOptions& o, const std::vector<std::pair<std::size_t, std::size_t>>& chosen,
            const std::vector<double>& kept_lr, const std::vector<NoiseFit>& fits, SearchResult& res);

/// Out-of-sample gain and the outlier decision per channel (oos_gain.cpp).
void out_of_sample(const Design& d, const SearchOptions& o, SearchResult& res);

}  // namespace rnav::search_detail
