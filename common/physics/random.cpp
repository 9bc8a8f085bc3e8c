#include "common/physics/random.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav {

Rng::Rng(std::uint64_t seed, std::uint64_t realization, Stream stream) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(realization),
                    static_cast<std::uint32_t>(realization >> 32),
                    static_cast<std::uint32_t>(stream)};
  engine_.seed(seq);
}

GaussMarkov::GaussMarkov(double sigma, double tau_s) : sigma_(sigma), tau_s_(tau_s) {
  if (!(sigma >= 0) || !std::isfinite(sigma))
    throw std::invalid_argument("GaussMarkov: sigma must be finite and >= 0");
  if (!(tau_s > 0)) throw std::invalid_argument("GaussMarkov: tau_s must be > 0");
}

void GaussMarkov::start(Rng& rng) { x_ = sigma_ * rng.normal(); }

double GaussMarkov::step(double dt_s, Rng& rng) {
  if (!(dt_s >= 0)) throw std::invalid_argument("GaussMarkov::step: dt_s must be >= 0");
  // phi = exp(-dt/T); w ~ N(0, sigma^2 (1 - phi^2))
  const double phi = std::isinf(tau_s_) ? 1.0 : std::exp(-dt_s / tau_s_);
  const double q = sigma_ * sigma_ * (1.0 - phi * phi);
  x_ = phi * x_ + std::sqrt(q) * rng.normal();
  return x_;
}

}  // namespace rnav
