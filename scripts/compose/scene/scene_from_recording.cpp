#include "scripts/compose/scene/scene_from_recording.hpp"

#include <filesystem>

#include "common/physics/frames.hpp"
#include "sim/scene/scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace rnav {

namespace {

// The smallest arc holding every bearing: from the end of the largest gap between neighbours
// (sorted, circularly) to its start; widened by margin each side.
scene::Coverage arc_of(std::vector<double> b, double margin_rad) {
  scene::Coverage c;
  if (b.size() < 2) return c;
  for (double& x : b) x = std::fmod(std::fmod(x, 2 * M_PI) + 2 * M_PI, 2 * M_PI);
  std::sort(b.begin(), b.end());
  double gap = b.front() + 2 * M_PI - b.back();  // the wrap-around gap
  std::size_t after = 0;                        // the arc starts at b[after]
  for (std::size_t i = 1; i < b.size(); ++i)
    if (b[i] - b[i - 1] > gap) gap = b[i] - b[i - 1], after = i;
  const double span = 2 * M_PI - gap + 2 * margin_rad;
  if (span >= 2 * M_PI) return c;  // every bearing
  c.bearing_lo_rad = wrap_pi(b[after] - margin_rad);
  c.bearing_span_rad = span;
  return c;
}

using Key = std::tuple<std::string, double, double>;  // sensor, t_s, bearing_rad: a detection row

// A return within kNearGates gates of the reference of a target this sensor detects (range
// sensors: its position within kNearGates gate_position_m; bearing-only: its bearing within
// kNearGates gate_bearing_deg) that the association left out: the target's own (another point
// of its hull, a gross error), not clutter. The simulation makes that target's returns itself,
// so these are not replayed. A target the sensor never detects keeps the returns near it.
constexpr double kNearGates = 2;
bool near_a_target(const MultiSensorData& data, const Detection& d, const AssociationOptions& o, const SensorAssociation& st) {
  for (const auto& [t, track] : data.truth) {
    const auto n = st.associated.find(t);
    if (n == st.associated.end() || n->second == 0) continue;
    scene::LineOfSight los;
    if (!scene::line_of_sight(data.observer, track, d.t_s, o.reference_max_gap_s, los)) continue;
    if (std::isfinite(d.range_m)) {
      const Eigen::Vector2d p = d.range_m * Eigen::Vector2d(std::sin(d.bearing_rad), std::cos(d.bearing_rad));
      if ((p - los.d).norm() <= kNearGates * o.gate_position_m) return true;
    } else if (std::abs(wrap_pi(d.bearing_rad - los.bearing_rad)) <= kNearGates * o.gate_bearing_deg * M_PI / 180) {
      return true;
    }
  }
  return false;
}

// A sensor the association read as rotations of period P and direction dir (it stamps each
// detection at its own time; rotation_scans.hpp): its beam, b(t) = b0 + dir w (t - t0), t0 its
// first detection, fitted to every detection (clutter included: the same beam lights it). A
// period off by 1e-4 turns the beam 13 deg off over 900 s, so the phase and the rate are fitted
// together: from b0 the circular mean of b_i - dir w (t_i - t0) over the first kPhaseRotations
// rotations and w = 2 pi / P, each pass regresses
//   e_i = wrap(b_i - b(t_i)) = db0 + dir dw (t_i - t0)
// by least squares on the detections within kBeamTrimDeg of the beam (an echo stamped late, a
// merge) and moves b0 and w by its solution; kBeamPasses passes.
constexpr int kPhaseRotations = 10;
constexpr int kBeamPasses = 3;
constexpr double kBeamTrimDeg = 5;
scene::Rotation rotation_of(const std::vector<Detection>& det, const std::string& sensor, double period_s, int direction) {
  scene::Rotation r;
  std::vector<double> t, b;
  for (const auto& d : det)
    if (d.sensor == sensor && !d.empty_scan()) t.push_back(d.t_s), b.push_back(d.bearing_rad);
  if (t.empty() || direction == 0) return r;  // not rotating after all: scans as stamped
  r.direction = direction;
  r.t0_s = t.front();
  double w = 2 * M_PI / period_s, c = 0, sn = 0;
  for (std::size_t i = 0; i < t.size() && t[i] - r.t0_s < kPhaseRotations * period_s; ++i) {
    const double phi = b[i] - r.direction * w * (t[i] - r.t0_s);
    c += std::cos(phi), sn += std::sin(phi);
  }
  double b0 = std::atan2(sn, c);
  for (int pass = 0; pass < kBeamPasses; ++pass) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d y = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double dt = t[i] - r.t0_s, ei = wrap_pi(b[i] - b0 - r.direction * w * dt);
      if (std::abs(ei) > kBeamTrimDeg * M_PI / 180) continue;
      const Eigen::Vector2d x(1.0, r.direction * dt);
      A += x * x.transpose(), y += x * ei;
    }
    if (A.determinant() <= 0) break;
    const Eigen::Vector2d s = A.ldlt().solve(y);
    b0 += s(0), w += s(1);
  }
  r.period_s = 2 * M_PI / w;
  r.b0_rad = wrap_pi(b0);
  return r;
}

}  // namespace

scene::RecordedScene scene_from_recording(const MultiSensorData& data, const std::string& name, const AssociationOptions& o) {
  std::map<std::string, SensorAssociation> stats;
  const std::vector<AssociatedDetection> a = associate(data, o, stats);
  scene::RecordedScene sc;
  sc.name = name;
  sc.observer = data.observer;
  sc.observer_heading_deg = data.observer_heading_deg;
  sc.targets = data.truth;
  sc.reference_max_gap_s = o.reference_max_gap_s;
  sc.min_speed_mps = o.min_speed_mps;
  std::set<Key> associated;
  std::map<std::string, std::vector<double>> assoc_range;  // per sensor: ranges of its associated detections (or predicted)
  for (const auto& x : a) {
    associated.insert({x.sensor, x.t_s, x.bearing_rad});
    assoc_range[x.sensor].push_back(x.has_range ? x.range_m : x.range_pred());
  }
  for (const std::string& s : data.sensors()) {
    scene::SceneSensor ss;
    ss.name = s;
    std::vector<double> bearings;
    for (const auto& d : data.detections) {
      if (d.sensor != s) continue;
      if (ss.scan_times_s.empty() || d.t_s > ss.scan_times_s.back()) ss.scan_times_s.push_back(d.t_s);
      if (d.empty_scan()) continue;
      bearings.push_back(d.bearing_rad);
      if (std::isfinite(d.range_m)) ss.ranged = true;
      if (!associated.count({s, d.t_s, d.bearing_rad}) && !near_a_target(data, d, o, stats[s])) ss.clutter.push_back({d.range_m, d.bearing_rad, d.t_s});
    }
    std::vector<double> dt;
    for (std::size_t i = 1; i < ss.scan_times_s.size(); ++i) dt.push_back(ss.scan_times_s[i] - ss.scan_times_s[i - 1]);
    if (!dt.empty()) {
      std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
      ss.scan_period_s = dt[dt.size() / 2];
    }
    if (!(ss.scan_period_s > 0)) ss.scan_period_s = 1;
    if (stats[s].rotation_period_s > 0) {
      ss.rotation = rotation_of(data.detections, s, stats[s].rotation_period_s, stats[s].rotation_direction);
      if (ss.rotation.rotating()) ss.scan_period_s = ss.rotation.period_s;
    }
    ss.coverage = arc_of(bearings, kCoverageMarginDeg * M_PI / 180);
    auto& rr = assoc_range[s];
    if (!rr.empty()) {
      const auto [lo, hi] = std::minmax_element(rr.begin(), rr.end());
      const double w = kCoverageMarginFrac * (*hi - *lo);
      ss.coverage.range_lo_m = std::max(0.0, *lo - w);
      ss.coverage.range_hi_m = std::max(*hi + w, ss.coverage.range_lo_m + 1);
    }
    const double scans = ss.rotation.rotating() ? static_cast<double>(ss.rotation.rotations_until(ss.scan_times_s.back()))
                                                : static_cast<double>(ss.scan_times_s.size());
    ss.clutter_per_scan = static_cast<double>(ss.clutter.size()) / scans;
    for (const auto& [t, track] : data.truth) ss.p_detect[t] = 1.0;  // calibrate_detection sets them
    sc.sensors.push_back(std::move(ss));
  }
  return sc;
}

void calibrate_detection(scene::RecordedScene& sc, const MultiSensorData& real, const scene::SceneErrors& errors,
                         const AssociationOptions& o, std::uint64_t seed) {
  // a realization beyond any ensemble's (2^63): its streams are no simulation's
  constexpr std::uint64_t kCalibration = std::uint64_t{1} << 63;
  for (auto& s : sc.sensors)
    for (auto& [t, p] : s.p_detect) p = 1.0;
  std::map<std::string, SensorAssociation> st_real, st_all;
  associate(real, o, st_real);
  associate(recording_of(real, scene::simulate(sc, errors, seed, kCalibration)), o, st_all);
  for (auto& s : sc.sensors)
    for (auto& [t, p] : s.p_detect) {
      const auto count = [&](const std::map<std::string, SensorAssociation>& st) {
        const auto i = st.find(s.name);
        if (i == st.end()) return 0;
        const auto j = i->second.associated.find(t);
        return j == i->second.associated.end() ? 0 : j->second;
      };
      const int all = count(st_all);
      p = all > 0 ? std::min(1.0, static_cast<double>(count(st_real)) / all) : 0.0;
    }
}

std::string recording_folder_name(const std::string& dir) {
  std::filesystem::path p(dir);
  if (p.filename().empty()) p = p.parent_path();
  return p.filename().string();
}

MultiSensorData recording_of(const MultiSensorData& real, const std::vector<scene::SceneDetection>& det) {
  MultiSensorData d;
  d.observer = real.observer;
  d.observer_heading_deg = real.observer_heading_deg;
  d.truth = real.truth;
  d.hull = real.hull;
  d.simulated = true;
  d.detections.reserve(det.size());
  for (const auto& x : det) d.detections.push_back({x.t_s, x.sensor, x.range_m, x.bearing_rad, NAN});
  // file order: per sensor non-decreasing t_s (simulate() gives sensor by sensor, each in time order)
  return d;
}

}  // namespace rnav
