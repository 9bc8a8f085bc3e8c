// The set of realizations an ensemble's statistics hold, as JSON closed intervals
// [[first, last], ...] (ensemble_state.json's "held"): compact for contiguous shards.
#pragma once

#include <nlohmann/json.hpp>

#include <set>
#include <stdexcept>
#include <string>

namespace rnav {

inline nlohmann::ordered_json realization_intervals(const std::set<long>& held) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (auto it = held.begin(); it != held.end();) {
    const long a = *it;
    long b = a;
    while (++it != held.end() && *it == b + 1) ++b;
    j.push_back({a, b});
  }
  return j;
}

/// Inverse of realization_intervals(); throws std::invalid_argument naming `what` on anything
/// but ordered, disjoint intervals of indices >= 0.
inline std::set<long> realization_set(const nlohmann::json& j, const std::string& what) {
  std::set<long> held;
  if (!j.is_array()) throw std::invalid_argument(what + ": 'held' must be a list of [first, last] intervals");
  long next = 0;
  for (const auto& iv : j) {
    if (!iv.is_array() || iv.size() != 2 || !iv[0].is_number_integer() || !iv[1].is_number_integer() ||
        iv[0].get<long>() < next || iv[1].get<long>() < iv[0].get<long>())
      throw std::invalid_argument(what + ": 'held' must hold ordered disjoint intervals [first, last] of indices >= 0, got " +
                                  iv.dump());
    for (long r = iv[0].get<long>(); r <= iv[1].get<long>(); ++r) held.insert(held.end(), r);
    next = iv[1].get<long>() + 1;
  }
  return held;
}

}  // namespace rnav
