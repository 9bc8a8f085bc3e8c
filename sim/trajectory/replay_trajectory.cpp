#include "sim/trajectory/replay_trajectory.hpp"

#include "common/io/csv_table.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rnav {

namespace {
std::string num(double v) { return value_text(v); }
}  // namespace

ReplayTrajectory::ReplayTrajectory(const std::string& csv_file, const LocalLevelFrame& frame_L,
                                   double smoothing_s, double max_gap_s)
    : w_s_(smoothing_s) {
  const CsvTable t = CsvTable::read(csv_file, {"t_s", "lat_deg", "lon_deg", "h_m"});
  if (t.rows() < 3)
    throw ConfigError(csv_file + ": " + std::to_string(t.rows()) +
                      " data rows; a replay needs at least 3 (trajectory.replay_csv)");
  t.require_time_order("t_s", false);
  const auto &ts = t.col("t_s"), &lat = t.col("lat_deg"), &lon = t.col("lon_deg"), &h = t.col("h_m");
  double largest_step = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const std::string where = csv_file + ":" + std::to_string(t.line(i)) + ": ";
    if (std::abs(lat[i]) > 90) throw ConfigError(where + "column 'lat_deg': " + num(lat[i]) + " is outside [-90, 90]");
    if (lon[i] < -180 || lon[i] > 360)
      throw ConfigError(where + "column 'lon_deg': " + num(lon[i]) + " is outside [-180, 360]");
    if (h[i] < -1000 || h[i] > 20000)
      throw ConfigError(where + "column 'h_m': " + num(h[i]) + " is outside [-1000, 20000] m");
    if (i > 0) {
      const double step = ts[i] - ts[i - 1];
      if (step > max_gap_s)
        throw ConfigError(where + "gap of " + num(step) + " s after t_s = " + num(ts[i - 1]) +
                          " exceeds trajectory.replay_max_gap_s = " + num(max_gap_s) + " s");
      largest_step = std::max(largest_step, step);
    }
    t_.push_back(ts[i] - ts[0]);
    p_TA_L_.push_back(frame_L.from_geodetic({lat[i], lon[i], h[i]}));
  }
  // With W > 2 x the largest step every window holds at least 3 samples with positive weight
  // (the worst case is t at an end: samples at 0, g1, g1 + g2 < W), so the fit is determined.
  if (!(smoothing_s > 2 * largest_step))
    throw ConfigError(csv_file + ": trajectory.replay_smoothing_s = " + num(smoothing_s) +
                      " s must exceed twice the file's largest time step (" + num(largest_step) +
                      " s)");
}

ReplayTrajectory::Weights ReplayTrajectory::weights(double t_s) const {
  const double t = std::clamp(t_s, 0.0, t_.back());
  // Samples with |t_i - t| < W.
  const auto lo = std::upper_bound(t_.begin(), t_.end(), t - w_s_);
  const auto hi = std::lower_bound(t_.begin(), t_.end(), t + w_s_);
  Weights r;
  r.first = static_cast<std::size_t>(lo - t_.begin());
  const std::size_t n = static_cast<std::size_t>(hi - lo);
  // Normal equations in the scaled time s_i = (t_i - t) / W (for conditioning), basis
  // x_i = (1, s_i, s_i^2), tricube weights w_i = (1 - |s_i|^3)^3:
  //   A = sum_i w_i x_i x_i^T,   p(t) = sum_i l_i p_i,   l_i = e0^T A^-1 w_i x_i.
  // Velocity = the exact time derivative of p(t) (weights and window move with t; ds/dt = -1/W):
  //   d_i = dl_i/dt = e0^T A^-1 (d(w_i x_i)/dt - (dA/dt) A^-1 w_i x_i),
  //   d(w x)/dt = -(w'(s) x + w x'(s)) / W,   w'(s) = -9 s |s| (1 - |s|^3)^2,   x'(s) = (0, 1, 2 s).
  // For samples on a quadratic this equals the fitted slope; elsewhere it keeps v = dp/dt.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), dA = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Vector3d> b(n), db(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double s = (t_[r.first + k] - t) / w_s_, a = 1 - std::abs(s * s * s);
    const double w = a * a * a, dw_ds = -9 * s * std::abs(s) * a * a;
    const Eigen::Vector3d x(1, s, s * s), dx_ds(0, 1, 2 * s);
    b[k] = w * x;
    db[k] = -(dw_ds * x + w * dx_ds) / w_s_;
    A += b[k] * x.transpose();
    dA += -(dw_ds * x * x.transpose() + w * (dx_ds * x.transpose() + x * dx_ds.transpose())) / w_s_;
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
  // The constructor's W > 2 x step guarantees 3 distinct samples with w > 0; a failure here
  // is a bug, not bad input.
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || std::abs(A.determinant()) < 1e-12)
    throw std::logic_error("ReplayTrajectory: singular smoothing fit at t = " + num(t) + " s");
  const Eigen::Vector3d g = ldlt.solve(Eigen::Vector3d::UnitX());  // A^-1 e0 (A symmetric)
  const Eigen::Vector3d gd = ldlt.solve(dA.transpose() * g);        // A^-1 dA^T A^-1 e0
  r.l.resize(n);
  r.d.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    r.l[k] = g.dot(b[k]);
    r.d[k] = g.dot(db[k]) - gd.dot(b[k]);
  }
  return r;
}

AircraftKinematics ReplayTrajectory::at(double t_s) const {
  const Weights w = weights(t_s);
  AircraftKinematics k;
  k.p_TA_L.setZero();
  k.v_A_L.setZero();
  for (std::size_t i = 0; i < w.l.size(); ++i) {
    k.p_TA_L += w.l[i] * p_TA_L_[w.first + i];
    k.v_A_L += w.d[i] * p_TA_L_[w.first + i];
  }
  return k;
}

}  // namespace rnav
