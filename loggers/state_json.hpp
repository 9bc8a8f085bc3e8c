// Reading and writing ensemble_state.json (PrlStats and UavStats): doubles as exact text, and
// members that are present and of the right kind or an error naming where in the file.
#pragma once

#include "common/physics/exact_sum.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace rnav::state_json {

/// x exactly: 17 significant digits, which read back as the same double.
inline std::string exact_text(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

/// A double written by exact_text() (or any decimal) from a JSON string; NaN is refused, and
/// so are infinities when `finite`. Errors name `what`.
inline double read_exact(const nlohmann::json& j, const std::string& what, bool finite) {
  if (!j.is_string()) throw std::invalid_argument(what + ": expected a number as text");
  const std::string t = j.get<std::string>();
  char* end = nullptr;
  const double x = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || std::isnan(x) || (finite && !std::isfinite(x)))
    throw std::invalid_argument(what + ": not a " + (finite ? "finite " : "") + "number: '" + t + "'");
  return x;
}

/// j[key], or an error naming `what` when j is no object or has no such member.
inline const nlohmann::json& member(const nlohmann::json& j, const char* key, const std::string& what) {
  if (!j.is_object() || !j.contains(key)) throw std::invalid_argument(what + ": '" + key + "' is missing");
  return j.at(key);
}

/// j[key] as an exact sum (ExactSum::to_text), or an error naming `what`.
inline ExactSum exact_sum_member(const nlohmann::json& j, const char* key, const std::string& what) {
  const auto& v = member(j, key, what);
  if (!v.is_string()) throw std::invalid_argument(what + "." + key + ": expected an exact sum as text");
  return ExactSum::from_text(v.get<std::string>(), what + "." + key);
}

/// j[key] as an integer, or an error naming `what`.
template <class T> T int_member(const nlohmann::json& j, const char* key, const std::string& what) {
  const auto& v = member(j, key, what);
  if (!v.is_number_integer()) throw std::invalid_argument(what + "." + key + ": expected an integer");
  return v.get<T>();
}

}  // namespace rnav::state_json
