#include "multi_association.hpp"

#include "config.hpp"
#include "plane_series.hpp"

#include <cmath>
#include <limits>

namespace rnav {

std::vector<AssociatedDetection> associate(const MultiSensorData& data, const AssociationOptions& o,
                                           std::map<std::string, SensorAssociation>& stats) {
  if (!(o.gate_bearing_deg > 0 && o.gate_bearing_deg <= 45)) throw ConfigError("association: gate_bearing_deg must be in (0, 45]");
  if (!(o.gate_position_m > 0)) throw ConfigError("association: gate_position_m must be > 0");
  if (!(o.reference_max_gap_s > 0) || !std::isfinite(o.reference_max_gap_s))
    throw ConfigError("association: reference_max_gap_s must be finite and > 0");
  if (data.truth.empty()) throw ConfigError("multi-sensor diagnosis: needs truth.csv (the targets' reference tracks)");
  const LocalLevelFrame F(data.observer.front().g, 0.0);
  const PlaneSeries observer(data.observer, F);
  std::map<std::string, PlaneSeries> truth;
  const auto level = data.truth_on_level();
  for (const auto& [name, v] : level) truth.emplace(name, PlaneSeries(v, F, o.reference_max_gap_s));
  const double gate_b = o.gate_bearing_deg * kDegToRad, h = o.velocity_half_span_s;

  std::vector<AssociatedDetection> out;
  std::size_t i = 0;
  const auto& det = data.detections;
  // scans: consecutive rows of one sensor with one t_s (sensors may interleave between scans)
  while (i < det.size()) {
    std::size_t j = i + 1;
    while (j < det.size() && det[j].sensor == det[i].sensor && det[j].t_s == det[i].t_s) ++j;
    const std::string& sensor = det[i].sensor;
    const double t = det[i].t_s;
    SensorAssociation& st = stats[sensor];
    ++st.scans;
    std::vector<std::size_t> rows;
    for (std::size_t k = i; k < j; ++k)
      if (!det[k].empty_scan()) rows.push_back(k);
    st.detections += static_cast<int>(rows.size());
    const bool ranged = !rows.empty() && std::isfinite(det[rows[0]].range_m);
    Eigen::Vector2d po, vo;
    struct Pred {
      std::string target;
      Eigen::Vector2d p, v;
    };
    std::vector<Pred> preds;
    // gamma: the observer's local north, clockwise from the frame's north (meridian convergence,
    // about dlon sin(lat): 0.2 deg after 20 km east at 63 deg N). Bearings are measured from the
    // local north, so every vector below is turned into the observer's local orientation.
    double gamma = 0;
    if (observer.at(t, po) && observer.velocity(t, h, vo)) {
      const Eigen::Vector3d north_F = F.from_ned(F.to_geodetic(Eigen::Vector3d(po.x(), 0.0, po.y())), Eigen::Vector3d::UnitX());
      gamma = std::atan2(north_F.z(), north_F.x());
      for (const auto& [name, series] : truth) {
        Pred pr{name, {}, {}};
        if (series.at(t, pr.p) && series.velocity(t, h, pr.v)) preds.push_back(pr);
      }
    }
    const Eigen::Rotation2Dd to_local(-gamma);
    // distance of detection k from prediction p (metres or radians; its bearing turned into the frame)
    auto dist = [&](std::size_t k, const Eigen::Vector2d& p) {
      const Eigen::Vector2d d = p - po;
      const double b_F = det[k].bearing_rad + gamma;
      if (ranged) {
        const Eigen::Vector2d q = po + det[k].range_m * Eigen::Vector2d(std::cos(b_F), std::sin(b_F));
        return (q - p).norm();
      }
      return std::abs(wrap_pi(b_F - std::atan2(d.y(), d.x())));
    };
    const double gate = ranged ? o.gate_position_m : gate_b;
    // ambiguity: two predictions within one gate of each other
    std::vector<char> ambiguous(preds.size(), 0);
    for (std::size_t a = 0; a < preds.size(); ++a)
      for (std::size_t b = a + 1; b < preds.size(); ++b) {
        const Eigen::Vector2d da = preds[a].p - po, db = preds[b].p - po;
        const double sep = ranged ? (preds[a].p - preds[b].p).norm()
                                  : std::abs(wrap_pi(std::atan2(da.y(), da.x()) - std::atan2(db.y(), db.x())));
        if (sep < 2 * gate) ambiguous[a] = ambiguous[b] = 1;
      }
    if (std::any_of(ambiguous.begin(), ambiguous.end(), [](char c) { return c; })) ++st.ambiguous_scans;
    std::vector<long> claim(preds.size(), -1);
    for (std::size_t a = 0; a < preds.size(); ++a) {
      if (ambiguous[a]) continue;
      double best = std::numeric_limits<double>::infinity();
      for (auto k : rows)
        if (dist(k, preds[a].p) < best) best = dist(k, preds[a].p), claim[a] = static_cast<long>(k);
      if (!(best <= gate)) claim[a] = -1;
    }
    for (std::size_t a = 0; a < preds.size(); ++a) {
      if (ambiguous[a]) continue;
      bool lost = claim[a] < 0;
      for (std::size_t b = 0; b < preds.size() && !lost; ++b)
        if (b != a && claim[b] == claim[a] &&
            dist(static_cast<std::size_t>(claim[a]), preds[b].p) < dist(static_cast<std::size_t>(claim[a]), preds[a].p))
          lost = true;
      if (lost) {
        ++st.missed[preds[a].target];
        continue;
      }
      const Detection& dk = det[static_cast<std::size_t>(claim[a])];
      AssociatedDetection x;
      x.t_s = t;
      x.sensor = sensor;
      x.target = preds[a].target;
      x.has_range = ranged;
      x.bearing_rad = dk.bearing_rad;
      x.range_m = ranged ? dk.range_m : 0.0;
      x.d = to_local * (preds[a].p - po);
      x.v_target = to_local * preds[a].v;
      x.v_rel = to_local * (preds[a].v - vo);
      const double speed = preds[a].v.norm();
      x.u_course = speed > o.min_speed_mps ? Eigen::Vector2d(preds[a].v / speed) : Eigen::Vector2d::Zero();
      if (x.d.norm() < 1.0) continue;  // on top of the observer: no bearing
      out.push_back(x);
      ++st.associated[x.target];
    }
    i = j;
  }
  return out;
}

}  // namespace rnav
