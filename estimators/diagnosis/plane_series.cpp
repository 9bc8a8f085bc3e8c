#include "estimators/diagnosis/plane_series.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav {

PlaneSeries::PlaneSeries(const std::vector<GeoSample>& v, const LocalLevelFrame& F, double max_gap_s)
    : v_(v), max_gap_s_(max_gap_s) {
  if (!(max_gap_s > 0)) throw std::invalid_argument("PlaneSeries: max_gap_s must be > 0");
  for (const auto& s : v) {
    const Eigen::Vector3d q = F.from_geodetic(s.g);
    p_.emplace_back(q.x(), q.z());
  }
  // a_k = 2 ((p_(k+1) - p_k) / dt_2 - (p_k - p_(k-1)) / dt_1) / (dt_1 + dt_2)
  double sum = 0;
  int n = 0;
  for (std::size_t k = 1; k + 1 < p_.size(); ++k) {
    const double dt1 = v[k].t_s - v[k - 1].t_s, dt2 = v[k + 1].t_s - v[k].t_s;
    if (!(dt1 > 0 && dt2 > 0 && dt1 <= max_gap_s && dt2 <= max_gap_s)) continue;
    const Eigen::Vector2d a = 2 * ((p_[k + 1] - p_[k]) / dt2 - (p_[k] - p_[k - 1]) / dt1) / (dt1 + dt2);
    sum += a.squaredNorm() / 2, ++n;
  }
  accel_rms_ = n > 0 ? std::sqrt(sum / n) : 0.0;
}

bool PlaneSeries::bridge(double t, double& b_s2, double& interval_s) const {
  Eigen::Vector2d unused;
  if (!at(t, unused)) return false;
  if (t == v_.front().t_s) return b_s2 = 0, interval_s = v_.size() > 1 ? v_[1].t_s - v_[0].t_s : 0.0, true;
  const auto it = std::lower_bound(v_.begin(), v_.end(), t, [](const GeoSample& s, double x) { return s.t_s < x; });
  const auto i = static_cast<std::size_t>(it - v_.begin());
  b_s2 = (t - v_[i - 1].t_s) * (v_[i].t_s - t);
  interval_s = v_[i].t_s - v_[i - 1].t_s;
  return true;
}

bool PlaneSeries::at(double t, Eigen::Vector2d& out) const {
  if (v_.empty() || t < v_.front().t_s || t > v_.back().t_s) return false;
  if (t == v_.front().t_s) {
    out = p_.front();
    return true;
  }
  const auto it = std::lower_bound(v_.begin(), v_.end(), t, [](const GeoSample& s, double x) { return s.t_s < x; });
  const auto i = static_cast<std::size_t>(it - v_.begin());
  const double t0 = v_[i - 1].t_s, t1 = v_[i].t_s;
  if (t1 - t0 > max_gap_s_) return false;
  const double w = (t - t0) / (t1 - t0);
  out = (1 - w) * p_[i - 1] + w * p_[i];
  return true;
}

bool PlaneSeries::velocity(double t, double h, Eigen::Vector2d& out) const {
  Eigen::Vector2d a, b;
  if (!at(t - h, a) || !at(t + h, b)) return false;
  out = (b - a) / (2 * h);
  return true;
}

double PlaneSeries::t_first() const { return v_.empty() ? 0.0 : v_.front().t_s; }
double PlaneSeries::t_last() const { return v_.empty() ? 0.0 : v_.back().t_s; }

}  // namespace rnav
