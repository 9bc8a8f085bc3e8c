#include "common/io/tma_estimator_names.hpp"

namespace rnav {

const std::vector<std::string>& tma_estimator_names() {
  static const std::vector<std::string> names{"ekf", "rpekf", "ml", "pf"};
  return names;
}

}  // namespace rnav
