#include "common/physics/prl_effect_columns.hpp"

#include <cmath>
#include <stdexcept>

namespace rnav::prl_effect {

namespace {
Eigen::Vector3d unit(int channel, double x) {
  if (channel < 0 || channel >= kChannels) throw std::invalid_argument("prl_effect: channel must be 0, 1 or 2");
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  v(channel) = x;
  return v;
}
}  // namespace

// dD = g D
Eigen::Vector3d range_gain(const PlotGeometry& g) { return {g.range_m, 0, 0}; }

// d zeta = -zeta_dot tau
Eigen::Vector3d time_offset(const PlotGeometry& g) { return -g.rate; }

// dEg = k cot(Eg)
Eigen::Vector3d elevation_refraction(const PlotGeometry& g) { return {0, 0, 1.0 / std::tan(g.glide_rad)}; }

// dEk = c tan(Eg)
Eigen::Vector3d azimuth_elevation_coupling(const PlotGeometry& g) { return {0, std::tan(g.glide_rad), 0}; }

// d zeta = J R_R_ENU delta_ENU
Eigen::Matrix3d site_offset(const PlotGeometry& g, const Eigen::Matrix3d& R_R_ENU) { return g.J * R_R_ENU; }

// d zeta_c = rate (t - t0)
Eigen::Vector3d bias_drift(const PlotGeometry& g, int channel, double t0_s) { return unit(channel, g.t_s - t0_s); }

// d zeta_c = size 1[t >= t_step]
Eigen::Vector3d bias_step(const PlotGeometry& g, int channel, double t_step_s) {
  return unit(channel, g.t_s >= t_step_s ? 1.0 : 0.0);
}

// d zeta_c = a_sin sin(2 pi t / P) + a_cos cos(2 pi t / P)
Eigen::Matrix<double, 3, 2> periodic(const PlotGeometry& g, int channel, double period_s) {
  if (!(period_s > 0)) throw std::invalid_argument("prl_effect: periodic needs a period > 0 s");
  const double w = 2 * M_PI * g.t_s / period_s;
  Eigen::Matrix<double, 3, 2> m;
  m << unit(channel, std::sin(w)), unit(channel, std::cos(w));
  return m;
}

Eigen::Matrix3d R_R_ENU(double azimuth_reference_deg) {
  const double b = azimuth_reference_deg * M_PI / 180;
  Eigen::Matrix3d R;
  R << std::sin(b), std::cos(b), 0, 0, 0, 1, std::cos(b), -std::sin(b), 0;
  return R;
}

}  // namespace rnav::prl_effect
