// Internal to the effect search: the constant offsets no named effect explains on the channels
// of one offset group (a sensor's quantity on many targets), as a random effect across the
// targets (effect_search.hpp's OffsetGroup), and each grouped channel's drawn noise identified
// about its own mean (a simulation draws the offset from the group and the noise about it).
#pragma once

#include "estimators/model_id/entry_tests.hpp"

namespace rnav::search_detail {

/// res.offsets, and res.noise[c].drawn / offset_group of the grouped channels. Runs after the
/// drawn noise (it replaces it on the grouped channels); chosen: the final model.
void offset_groups(const Design& d, const SearchOptions& o, const Chosen& chosen, SearchResult& res);

}  // namespace rnav::search_detail
