#include "estimators/model_id/shown_unit.hpp"

#include <cmath>

namespace rnav {

namespace {
bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

ShownUnit shown_unit(const std::string& name) {
  const double deg = 180.0 / M_PI;
  if (name == "1") return {"ratio", 1.0};  // a dimensionless parameter (e.g. a range gain)
  if (name == "rad") return {"deg", deg};
  if (name == "rad_per_s") return {"deg_per_s", deg};
  if (ends_with(name, "_rad")) return {name.substr(0, name.size() - 3) + "deg", deg};
  if (ends_with(name, "_radps")) return {name.substr(0, name.size() - 5) + "degps", deg};
  return {name, 1.0};
}

}  // namespace rnav
