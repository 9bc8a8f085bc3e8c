#include "sim/scene/scene_geometry.hpp"

#include <GeographicLib/LocalCartesian.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rnav::scene {

bool track_at(const std::vector<GeoSample>& track, double t, double max_gap_s, Geodetic& out) {
  if (track.empty() || t < track.front().t_s || t > track.back().t_s) return false;
  auto it = std::lower_bound(track.begin(), track.end(), t, [](const GeoSample& s, double x) { return s.t_s < x; });
  if (it->t_s == t) {
    out = it->g;
    return true;
  }
  const GeoSample& b = *it;
  const GeoSample& a = *(it - 1);
  if (b.t_s - a.t_s > max_gap_s) return false;
  // linear between the samples: w = (t - t_a) / (t_b - t_a)
  const double w = (t - a.t_s) / (b.t_s - a.t_s);
  out.lat_deg = a.g.lat_deg + w * (b.g.lat_deg - a.g.lat_deg);
  out.lon_deg = a.g.lon_deg + w * (b.g.lon_deg - a.g.lon_deg);
  out.h_m = a.g.h_m + w * (b.g.h_m - a.g.h_m);
  return true;
}

namespace {

// The track's position at t in the tangent plane lc (east, north), at height h (2-D).
bool plane_at(const GeographicLib::LocalCartesian& lc, const std::vector<GeoSample>& track, double t, double max_gap_s,
              double h, Eigen::Vector2d& p) {
  Geodetic g;
  if (!track_at(track, t, max_gap_s, g)) return false;
  double x, y, z;
  lc.Forward(g.lat_deg, g.lon_deg, h, x, y, z);
  p = {x, y};
  return true;
}

// d p / dt at t by central differences over +-hs, one-sided (or shorter) at the track's ends.
bool velocity(const GeographicLib::LocalCartesian& lc, const std::vector<GeoSample>& track, double t, double max_gap_s,
              double h, double hs, Eigen::Vector2d& v) {
  const double t0 = std::max(t - hs, track.front().t_s), t1 = std::min(t + hs, track.back().t_s);
  Eigen::Vector2d p0, p1;
  if (!(t1 > t0) || !plane_at(lc, track, t0, max_gap_s, h, p0) || !plane_at(lc, track, t1, max_gap_s, h, p1)) return false;
  v = (p1 - p0) / (t1 - t0);
  return true;
}

}  // namespace

bool line_of_sight(const std::vector<GeoSample>& observer, const std::vector<GeoSample>& target, double t, double max_gap_s,
                   LineOfSight& los, double half_span_s) {
  constexpr double kNoGap = std::numeric_limits<double>::infinity();
  Geodetic o;
  if (!track_at(observer, t, kNoGap, o)) return false;
  const GeographicLib::LocalCartesian lc(o.lat_deg, o.lon_deg, o.h_m);
  Eigen::Vector2d p, vo, vt;
  if (!plane_at(lc, target, t, max_gap_s, o.h_m, p)) return false;
  if (!velocity(lc, observer, t, kNoGap, o.h_m, half_span_s, vo) || !velocity(lc, target, t, max_gap_s, o.h_m, half_span_s, vt))
    return false;
  los.d = p;
  los.range_m = p.norm();
  if (!(los.range_m >= 1)) return false;
  los.bearing_rad = std::atan2(p.x(), p.y());  // clockwise from north: atan2(east, north)
  los.v_target = vt;
  los.v_rel = vt - vo;
  return true;
}

multi_effect::Geometry effect_geometry(const LineOfSight& los, bool is_range, double t, double min_speed_mps) {
  multi_effect::Geometry g;
  g.is_range = is_range;
  const double r = los.range_m;
  // range: d r / d d = d' / r; bearing beta = atan2(e, n): d beta / d(e, n) = (n, -e) / r^2
  if (is_range)
    g.dh = los.d.transpose() / r;
  else
    g.dh = Eigen::RowVector2d(los.d.y(), -los.d.x()) / (r * r);
  g.v_rel = los.v_rel;
  g.v_target = los.v_target;
  const double speed = los.v_target.norm();
  if (speed > min_speed_mps) {
    g.u = los.v_target / speed;
    g.u_perp = Eigen::Vector2d(g.u.y(), -g.u.x());  // (east, north): starboard of the course
  }
  g.range_pred = r;
  g.bearing_pred = los.bearing_rad;
  g.t = t;
  return g;
}

}  // namespace rnav::scene
