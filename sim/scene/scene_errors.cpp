#include "sim/scene/scene_errors.hpp"

#include "common/physics/multi_effect_columns.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav::scene {

std::string channel_name(const std::string& sensor, const std::string& target, bool is_range) {
  return sensor + ":" + target + (is_range ? ":range" : ":bearing");
}

NoiseParams SceneErrors::channel_noise(const std::string& name, bool is_range) const {
  const auto it = noise.find(name);
  if (it != noise.end()) return it->second;
  NoiseParams p;
  const double s = is_range ? nominal_range_sigma_m : nominal_bearing_sigma_rad;
  p.s2 = s * s;
  return p;
}

namespace {
// The number of columns of entry `name` (its parameters).
std::size_t columns_of(const std::string& name) {
  multi_effect::Geometry g;
  g.is_range = name == "range_bias" || name == "echo_range_offset" || name == "near_side_echo" || name == "range_gain";
  return static_cast<std::size_t>(multi_effect::columns(name, g, 0, 1).size());
}
}  // namespace

void SceneErrors::check() const {
  if (!(nominal_bearing_sigma_rad > 0) || !(nominal_range_sigma_m > 0) || !std::isfinite(nominal_bearing_sigma_rad) ||
      !std::isfinite(nominal_range_sigma_m))
    throw std::invalid_argument("scene errors: the nominal sigmas must be finite and > 0");
  const auto& known = multi_effect::names();
  for (const auto& e : effects) {
    if (std::find(known.begin(), known.end(), e.name) == known.end())
      throw std::invalid_argument("scene errors: effect '" + e.name + "' is not one the simulation can make");
    if (e.theta.size() != columns_of(e.name))
      throw std::invalid_argument("scene errors: effect '" + e.name + "' takes " + std::to_string(columns_of(e.name)) +
                                  " parameter(s), not " + std::to_string(e.theta.size()));
    for (double x : e.theta)
      if (!std::isfinite(x)) throw std::invalid_argument("scene errors: effect '" + e.name + "' has a non-finite parameter");
    if (!std::isfinite(e.scan_value)) throw std::invalid_argument("scene errors: effect '" + e.name + "' has a non-finite scanned value");
  }
  for (const auto& [key, o] : offsets)
    if (!std::isfinite(o.mean) || !std::isfinite(o.sd) || !(o.sd >= 0))
      throw std::invalid_argument("scene errors: the target offsets of " + key + " need a finite mean and a finite sd >= 0");
  for (const auto& [name, p] : noise) {
    try {
      check_noise_params(p);
    } catch (const std::invalid_argument& x) {
      throw std::invalid_argument("scene errors: noise of channel " + name + ": " + x.what());
    }
  }
}

}  // namespace rnav::scene
