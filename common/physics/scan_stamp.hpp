// The time stamp of a rotating sensor that stamps a whole scan with one time: one model, used
// by whatever simulates such a sensor and by the diagnosis that fits it (scan_time_offset).
#pragma once

#include <cmath>

namespace rnav {

/// How late the stamp of a scan that ends at bearing beta_end_rad is for a detection at bearing
/// beta_rad, the beam turning clockwise (bearing increasing) once per period_s:
///   delay = ((beta_end - beta) mod 2 pi) / omega,  omega = 2 pi / period   [s], in [0, period).
/// Bearings [rad] clockwise from north, any range; period_s > 0 [s].
inline double sweep_delay_s(double beta_rad, double beta_end_rad, double period_s) {
  double a = std::fmod(beta_end_rad - beta_rad, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return period_s * a / (2 * M_PI);
}

}  // namespace rnav
