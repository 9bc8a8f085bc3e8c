// How the text reports show a value: angles in degrees (the unit of the data files, the options
// and the simulator's inputs), everything else in its own unit. The JSON reports keep radians.
#pragma once

#include <string>

namespace rnav {

struct ShownUnit {
  std::string name;    ///< the parameter name or unit as shown
  double factor = 1;   ///< shown value = factor * value
};

/// For a parameter name or a unit: "rad" -> "deg", "X_rad" -> "X_deg", "rad_per_s" ->
/// "deg_per_s", "X_radps" -> "X_degps" (factor 180 / pi); "1" (dimensionless) -> "ratio";
/// anything else unchanged (factor 1).
ShownUnit shown_unit(const std::string& name);

}  // namespace rnav
