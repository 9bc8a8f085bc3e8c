#include "estimators/model_id/ladder_curve.hpp"

#include "estimators/model_id/stats.hpp"

#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>

namespace rnav {

LadderOutcome ladder_on_curve(const HitCurve& k, double power, const InjectionOptions& io, std::uint64_t seed) {
  if (!(k.slope > 0) || !std::isfinite(k.slope)) throw std::invalid_argument("hit curve: slope must be finite and > 0");
  if (!(k.a_named > 0) || !std::isfinite(k.a_named) || !(k.a_detected > 0) || !(k.a_detected <= k.a_named))
    throw std::invalid_argument("hit curve: sizes must be finite, > 0, and a_detected <= a_named");
  if (!(power > 0 && power < 1)) throw std::invalid_argument("hit curve: power must be in (0, 1)");
  const double zp = normal_upper_quantile(1 - power);
  // P(hit | a) = Phi(slope log(a / a_p) + z_p): power at a = a_p
  auto rate = [&](double a, double a_p) { return a > 0 && std::isfinite(a) ? normal_cdf(k.slope * std::log(a / a_p) + zp) : 0.0; };
  std::atomic<int> drawn{0};  // every injection the ladder ran (threads may draw at once)
  const InjectionDraw draw = [&](double a, std::size_t b, int i) {
    ++drawn;
    std::seed_seq ss{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(b),
                     static_cast<std::uint32_t>(i)};
    std::mt19937_64 rng(ss);
    const double u = std::uniform_real_distribution<double>(0, 1)(rng);
    return InjectionHit{u < rate(a, k.a_named), u < rate(a, k.a_detected)};
  };
  const InjectedLimit L = measure_ladder(draw, 1.0, power, io);
  LadderOutcome out;
  out.injections = drawn;
  out.named_rate = rate(L.named.size, k.a_named);
  out.detected_rate = rate(L.detected.size, k.a_detected);
  return out;
}

}  // namespace rnav
