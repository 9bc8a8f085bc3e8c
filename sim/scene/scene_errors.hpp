// The errors a simulated scene's sensors make: named effects (the multi-sensor catalogue's,
// injected through the columns the diagnosis fits: common/physics/multi_effect_columns.hpp) and each
// channel's noise (common/physics/noise_process.hpp). A diagnosis report becomes one of these in the
// composition root (scripts/compose/scene/scene_effects_json.hpp); the nominal model is white
// noise at the nominal sigmas and no effect.
#pragma once

#include "common/physics/noise_process.hpp"

#include <map>
#include <set>
#include <string>
#include <vector>

namespace rnav::scene {

/// One effect: the catalogue's name, its scope ("" = every sensor / every target) and its
/// parameters in the catalogue's units (s, rad, m, 1), one per column.
struct InjectedEffect {
  std::string name;
  std::string sensor, target;  ///< scope; "" for all
  std::vector<double> theta;
  double scan_value = 0;       ///< a scanned entry's value (bias_step: time [s]; scan_time_offset: sweep end [deg])
};

/// The offsets no named effect explains on one sensor's quantity, a random effect across its
/// targets (the diagnosis's OffsetGroup): each channel of the sensor's quantity draws, once per
/// realization, a constant offset u ~ N(mean, sd^2), except the channels listed as explained (a
/// named effect of their own target stands for their offset).
struct TargetOffsets {
  double mean = 0;  ///< [rad or m] finite
  double sd = 0;    ///< [rad or m] finite, >= 0
  std::set<std::string> explained;  ///< channels ("sensor:target:quantity") that draw none
};

struct SceneErrors {
  std::vector<InjectedEffect> effects;
  /// Per "sensor:bearing" or "sensor:range": the targets' offsets (none: no offset drawn).
  std::map<std::string, TargetOffsets> offsets;
  /// Per channel "sensor:target:bearing" or "sensor:target:range": its noise; a channel without
  /// an entry takes the nominal white noise below.
  std::map<std::string, NoiseParams> noise;
  double nominal_bearing_sigma_rad = 0.5 * M_PI / 180;  ///< [rad] > 0
  double nominal_range_sigma_m = 1.0;                    ///< [m] > 0
  /// The noise of channel `name` (its entry, or the nominal white noise of its quantity).
  NoiseParams channel_noise(const std::string& name, bool is_range) const;
  /// Throws std::invalid_argument naming the first fault (an unknown effect name, a parameter
  /// count that does not match its columns, a non-finite value, noise out of range).
  void check() const;
};

/// The channel name of a sensor:target pair's quantity.
std::string channel_name(const std::string& sensor, const std::string& target, bool is_range);

}  // namespace rnav::scene
