#include "estimators/uav_tma/tma_options.hpp"

namespace rnav {

const std::vector<std::string>& TmaOptions::known_estimators() { return tma_estimator_names(); }

void check_tma(const TmaOptions& o) {
  if (o.bank_min_m >= o.bank_max_m)
    throw ConfigError("scenario key 'tma.bank_min_m' must be below tma.bank_max_m");
}

}  // namespace rnav
