// A multi-sensor diagnosis report (rnav_diagnose multi --json) as the errors of a simulated
// scene (sim/scene/scene_errors.hpp): each named mean effect with its scope and values, each
// channel's identified noise (white, Gauss-Markov, outliers). A pooled report's effects of
// another recording (scope.recording) and its other recordings' channels are left out; its
// hardware effects apply to every recording. Noise findings and the reference's manoeuvres
// (noise_scale, correlated_noise, outliers, target_maneuver) are read through the channels'
// noise and the replayed reference, not as effects.
#pragma once

#include "sim/scene/scene_errors.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace rnav {

/// The errors of recording `recording` in report j (from `source`, named in errors). The
/// nominal sigmas are the report's (each channel's sigma over its noise_scale) where it has
/// channels of that quantity, else nominal_bearing_sigma_rad / nominal_range_sigma_m. Throws
/// ConfigError naming source and the entry for a report of another kind, an unknown effect, a
/// value of the wrong shape, or a recording the pooled report does not hold. Each channel's noise
/// is the one the report says a simulation draws (its "simulated" model: the identified noise
/// with the slow wander no named effect explains), and each sensor's targets draw the offsets
/// no named effect explains (its "offsets": a random effect across the targets); or with
/// use_simulated false (or a report without them) the identified noise findings themselves
/// (fitted with a trend, correlation times up to a quarter of the series) and no offsets.
scene::SceneErrors errors_from_report(const nlohmann::json& j, const std::string& source, const std::string& recording,
                                      double nominal_bearing_sigma_rad, double nominal_range_sigma_m, bool use_simulated = true);

/// The nominal model: no effect, white noise at the nominal sigmas.
scene::SceneErrors nominal_errors(double nominal_bearing_sigma_rad, double nominal_range_sigma_m);

}  // namespace rnav
