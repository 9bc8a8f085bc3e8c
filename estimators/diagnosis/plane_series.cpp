#include "plane_series.hpp"

#include <algorithm>
#include <stdexcept>

namespace rnav {

PlaneSeries::PlaneSeries(const std::vector<GeoSample>& v, const LocalLevelFrame& F, double max_gap_s)
    : v_(v), max_gap_s_(max_gap_s) {
  if (!(max_gap_s > 0)) throw std::invalid_argument("PlaneSeries: max_gap_s must be > 0");
  for (const auto& s : v) {
    const Eigen::Vector3d q = F.from_geodetic(s.g);
    p_.emplace_back(q.x(), q.z());
  }
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
