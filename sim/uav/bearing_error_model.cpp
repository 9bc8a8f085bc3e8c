#include "bearing_error_model.hpp"

namespace rnav {

BearingErrorModel::BearingErrorModel(const SensorOptions& o) {
  effects_.push_back(std::make_unique<WhiteBearingNoise>(o.sigma_deg * kDegToRad));
}

void BearingErrorModel::start(Rng& rng) {
  for (auto& e : effects_) e->start(rng);
}

double BearingErrorModel::error(const BearingTruth& truth, Rng& rng) {
  double sum = 0;
  for (auto& e : effects_) sum += e->error(truth, rng);
  return sum;
}

}  // namespace rnav
