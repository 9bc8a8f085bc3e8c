#include "sim/uav/guidance.hpp"

#include "common/physics/frames.hpp"

#include <algorithm>
#include <cmath>

namespace rnav::guidance {

Limits Limits::from(const ObserverOptions& o) {
  Limits l;
  l.airspeed_mps = o.speed_mps;
  l.radius_m = o.radius_m;
  l.orbit_sense = o.direction == "cw" ? 1.0 : -1.0;
  l.standoff_gain = o.standoff_gain;
  l.time_constant_s = o.heading_time_constant_s;
  // omega_max = min(max_turn_rate, g tan(max_bank) / V_a)
  l.max_turn_rate_radps =
      std::min(o.max_turn_rate_dps * kDegToRad, kGravity * std::tan(o.max_bank_deg * kDegToRad) / o.speed_mps);
  l.wind_F = Eigen::Vector2d(o.wind_north_mps, o.wind_east_mps);
  return l;
}

double desired_course(const Limits& l, double beta_rad, std::optional<double> r_m) {
  // chi_d = beta - s (pi/2 - atan(k (r - R) / R))
  const double offset = r_m ? std::atan(l.standoff_gain * (*r_m - l.radius_m) / l.radius_m) : 0.0;
  return wrap_pi(beta_rad - l.orbit_sense * (M_PI / 2 - offset));
}

double heading_for_course(const Limits& l, double chi_rad) {
  // psi_d = chi_d - asin(w_perp / V_a), w_perp = u x w = u_n w_e - u_e w_n
  const double w_perp = std::cos(chi_rad) * l.wind_F.y() - std::sin(chi_rad) * l.wind_F.x();
  return wrap_pi(chi_rad - std::asin(std::clamp(w_perp / l.airspeed_mps, -1.0, 1.0)));
}

double turn_rate_command(const Limits& l, double heading_rad, double desired_heading_rad) {
  // omega = clamp(wrap(psi_d - psi) / tau + s V_a / R, +-omega_max)
  const double omega = wrap_pi(desired_heading_rad - heading_rad) / l.time_constant_s +
                       l.orbit_sense * l.airspeed_mps / l.radius_m;
  return std::clamp(omega, -l.max_turn_rate_radps, l.max_turn_rate_radps);
}

Eigen::Vector2d ground_velocity(const Limits& l, double heading_rad) {
  return l.airspeed_mps * Eigen::Vector2d(std::cos(heading_rad), std::sin(heading_rad)) + l.wind_F;
}

UavState propagate(const Limits& l, const UavState& x, double omega_radps, double dt_s) {
  UavState y;
  const double psi0 = x.heading_rad, psi1 = psi0 + omega_radps * dt_s;
  Eigen::Vector2d air;
  if (std::abs(omega_radps * dt_s) < 1e-9) {
    air = l.airspeed_mps * dt_s * Eigen::Vector2d(std::cos(psi0), std::sin(psi0));
  } else {
    // integral of V_a (cos psi, sin psi) dt with psi = psi0 + omega t
    air = l.airspeed_mps / omega_radps *
          Eigen::Vector2d(std::sin(psi1) - std::sin(psi0), std::cos(psi0) - std::cos(psi1));
  }
  y.p_OU_F = x.p_OU_F + air + l.wind_F * dt_s;
  y.heading_rad = wrap_pi(psi1);
  return y;
}

}  // namespace rnav::guidance
