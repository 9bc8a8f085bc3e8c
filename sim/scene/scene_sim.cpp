#include "sim/scene/scene_sim.hpp"

#include "common/physics/frames.hpp"
#include "common/physics/multi_effect_columns.hpp"
#include "sim/scene/scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace rnav::scene {

namespace {

// FNV-1a, 64 bit: a name's stream identifier (stable across runs and builds).
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

// The stream of (seed, realization, kind, name): kind 1 a sensor's detections and clutter, 2 a
// channel's noise.
std::mt19937_64 stream(std::uint64_t seed, std::uint64_t realization, std::uint32_t kind, const std::string& name) {
  const std::uint64_t h = fnv1a(name);
  std::seed_seq q{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(realization),
                  static_cast<std::uint32_t>(realization >> 32), kind, static_cast<std::uint32_t>(h),
                  static_cast<std::uint32_t>(h >> 32)};
  return std::mt19937_64(q);
}

bool in_scope(const InjectedEffect& e, const std::string& sensor, const std::string& target) {
  return (e.sensor.empty() || e.sensor == sensor) && (e.target.empty() || e.target == target);
}

// sum_e c_e(g) theta_e over the effects whose scope holds (sensor, target).
double effects_at(const SceneErrors& errors, const multi_effect::Geometry& g, const std::string& sensor, const std::string& target,
                  double period_s) {
  double y = 0;
  for (const auto& e : errors.effects) {
    if (!in_scope(e, sensor, target)) continue;
    const Eigen::RowVectorXd c = multi_effect::columns(e.name, g, e.scan_value, period_s);
    for (Eigen::Index k = 0; k < c.size(); ++k) y += c(k) * e.theta[static_cast<std::size_t>(k)];
  }
  return y;
}

// Channel ch's constant offset in this realization: u ~ N(mean, sd^2) of its sensor's quantity
// (SceneErrors::offsets), 0 where there is none or a named effect of its own stands for it.
// Its own stream (kind 3), so that the noise streams stay those of a scene without offsets.
double target_offset(const SceneErrors& errors, const std::string& sensor, const std::string& ch, bool is_range, std::uint64_t seed,
                     std::uint64_t realization) {
  const auto it = errors.offsets.find(sensor + (is_range ? ":range" : ":bearing"));
  if (it == errors.offsets.end() || it->second.explained.count(ch)) return 0;
  std::mt19937_64 rng = stream(seed, realization, 3, ch);
  std::normal_distribution<double> N(0.0, 1.0);
  return it->second.mean + it->second.sd * N(rng);
}

// A target's detection before its channel noise: the index into the output and its geometry.
struct Pending {
  std::size_t row;
  LineOfSight los;
};

// A target's detection in scan (or rotation) order: a uniform per target and scan whatever
// happens, so that the streams stay aligned; then its probability, its line of sight at t and
// the sensor's coverage.
void detect(const RecordedScene& scene, const SceneSensor& s, const std::string& name, const std::vector<GeoSample>& track, double t,
            double u, std::vector<SceneDetection>& out, std::map<std::string, std::vector<Pending>>& by_target) {
  const auto pd = s.p_detect.find(name);
  if (pd == s.p_detect.end() || !(u < pd->second)) return;
  LineOfSight los;
  if (!line_of_sight(scene.observer, track, t, scene.reference_max_gap_s, los)) return;
  if (!s.coverage.covers(los.bearing_rad, los.range_m)) return;
  by_target[name].push_back({out.size(), los});
  out.push_back({t, s.name, s.ranged ? los.range_m : NAN, los.bearing_rad, name});
}

// (x mod 2 pi) in [0, 2 pi)
double mod_2pi(double x) {
  const double m = std::fmod(x, 2 * M_PI);
  return m < 0 ? m + 2 * M_PI : m;
}

// The time within [start, start + P) at which a rotating beam lights bearing b:
//   t = start + P ((dir (b - b0)) mod 2 pi) / (2 pi)   (recorded_scene.hpp's Rotation; start = t0 + k P)
double lit_at(const Rotation& r, double start_s, double bearing_rad) {
  return start_s + r.period_s * mod_2pi(r.direction * (bearing_rad - r.b0_rad)) / (2 * M_PI);
}

// The time a moving target is lit in the rotation starting at start_s: the fixed point of
// t = lit_at(beta(t)), from the rotation's middle. The beam turns far faster than any bearing
// (a ship radar's 2.5 s period is 144 deg/s), so each step shrinks the error by that ratio and
// kLitIterations steps leave far less than kLitToleranceS. A target at the rotation's cut has no
// fixed point in it (the steps jump between its ends): it is lit in the neighbouring rotation,
// and not in this one. False then, or without a line of sight.
constexpr int kLitIterations = 6;
constexpr double kLitToleranceS = 1e-6;
bool target_lit(const RecordedScene& scene, const Rotation& r, const std::vector<GeoSample>& track, double start_s, double& t) {
  t = start_s + 0.5 * r.period_s;
  LineOfSight los;
  for (int i = 0; i < kLitIterations; ++i) {
    if (!line_of_sight(scene.observer, track, t, scene.reference_max_gap_s, los)) return false;
    const double next = lit_at(r, start_s, los.bearing_rad);
    const bool converged = std::abs(next - t) < kLitToleranceS;
    t = next;
    if (converged) return true;
  }
  return false;
}

// A sensor's scans at their stamps: target detections, clutter (replayed or drawn), an empty
// scan where nothing is in it.
void stamped_scans(const RecordedScene& scene, const SceneSensor& s, std::mt19937_64& rng, std::vector<SceneDetection>& out,
                   std::map<std::string, std::vector<Pending>>& by_target) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::poisson_distribution<int> clutter_count(s.clutter_per_scan > 0 ? s.clutter_per_scan : 1.0);
  std::size_t next_clutter = 0;  // replayed clutter: the first not yet passed
  for (double t : s.scan_times_s) {
    const std::size_t before = out.size();
    for (const auto& [name, track] : scene.targets) detect(scene, s, name, track, t, U(rng), out, by_target);
    if (s.replay_clutter) {  // the recording's own returns of this scan
      for (; next_clutter < s.clutter.size() && s.clutter[next_clutter].t_s <= t; ++next_clutter) {
        if (s.clutter[next_clutter].t_s < t) continue;  // a return between scans: none here
        out.push_back({t, s.name, s.ranged ? s.clutter[next_clutter].range_m : NAN, s.clutter[next_clutter].bearing_rad, ""});
      }
    } else {
      const int n_clutter = s.clutter_per_scan > 0 ? clutter_count(rng) : 0;
      for (int k = 0; k < n_clutter; ++k) {
        const auto i = std::min(static_cast<std::size_t>(U(rng) * static_cast<double>(s.clutter.size())), s.clutter.size() - 1);
        out.push_back({t, s.name, s.ranged ? s.clutter[i].range_m : NAN, s.clutter[i].bearing_rad, ""});
      }
    }
    if (out.size() == before) out.push_back({t, s.name, NAN, NAN, ""});  // an empty scan keeps the scan count
  }
}

// A rotating sensor's rotations from its first to its last recorded stamp: each target lit at
// its own time (kept inside the recorded span), clutter replayed at its recorded stamps or
// drawn per rotation and lit at its bearing. No empty scans (such a sensor writes none).
void rotations(const RecordedScene& scene, const SceneSensor& s, std::mt19937_64& rng, std::vector<SceneDetection>& out,
               std::map<std::string, std::vector<Pending>>& by_target) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::poisson_distribution<int> clutter_count(s.clutter_per_scan > 0 ? s.clutter_per_scan : 1.0);
  const Rotation& r = s.rotation;
  const double first = s.scan_times_s.front(), last = s.scan_times_s.back();
  const long n_rot = r.rotations_until(last);
  for (long k = 0; k < n_rot; ++k) {
    const double start = r.t0_s + static_cast<double>(k) * r.period_s;
    for (const auto& [name, track] : scene.targets) {
      const double u = U(rng);
      double t = 0;
      if (!target_lit(scene, r, track, start, t) || t < first || t > last) continue;
      detect(scene, s, name, track, t, u, out, by_target);
    }
    if (s.replay_clutter) continue;
    const int n_clutter = s.clutter_per_scan > 0 ? clutter_count(rng) : 0;
    for (int c = 0; c < n_clutter; ++c) {
      const auto i = std::min(static_cast<std::size_t>(U(rng) * static_cast<double>(s.clutter.size())), s.clutter.size() - 1);
      const double t = lit_at(r, start, s.clutter[i].bearing_rad);
      if (t >= first && t <= last) out.push_back({t, s.name, s.ranged ? s.clutter[i].range_m : NAN, s.clutter[i].bearing_rad, ""});
    }
  }
  if (s.replay_clutter)
    for (const ClutterSample& c : s.clutter) out.push_back({c.t_s, s.name, s.ranged ? c.range_m : NAN, c.bearing_rad, ""});
}

}  // namespace

std::vector<SceneDetection> simulate(const RecordedScene& scene, const SceneErrors& errors, std::uint64_t seed,
                                     std::uint64_t realization) {
  scene.check();
  errors.check();
  std::vector<SceneDetection> out;
  for (const SceneSensor& s : scene.sensors) {
    std::mt19937_64 rng = stream(seed, realization, 1, s.name);
    std::map<std::string, std::vector<Pending>> by_target;  // detections awaiting their channel's noise
    const std::size_t sensor_begin = out.size();
    if (s.rotation.rotating())
      rotations(scene, s, rng, out, by_target);
    else
      stamped_scans(scene, s, rng, out, by_target);
    // each channel: y = h + sum c theta + noise, the noise drawn over the channel's own times
    for (const auto& [name, list] : by_target) {
      for (const bool is_range : {false, true}) {
        if (is_range && !s.ranged) continue;
        const std::string ch = channel_name(s.name, name, is_range);
        std::vector<double> times;
        for (const auto& p : list) times.push_back(out[p.row].t_s);
        std::mt19937_64 nrng = stream(seed, realization, 2, ch);
        const Eigen::VectorXd noise = sample_noise(times, {}, errors.channel_noise(ch, is_range), nrng);
        const double offset = target_offset(errors, s.name, ch, is_range, seed, realization);
        for (std::size_t k = 0; k < list.size(); ++k) {
          SceneDetection& d = out[list[k].row];
          const multi_effect::Geometry g = effect_geometry(list[k].los, is_range, d.t_s, scene.min_speed_mps);
          const double dy = effects_at(errors, g, s.name, name, s.scan_period_s) + offset + noise(static_cast<Eigen::Index>(k));
          if (is_range)
            d.range_m = std::max(d.range_m + dy, 0.0);
          else
            d.bearing_rad = wrap_pi(d.bearing_rad + dy);
        }
      }
    }
    // a rotating sensor's returns in time order (each rotation's targets and clutter interleave)
    if (s.rotation.rotating())
      std::stable_sort(out.begin() + static_cast<std::ptrdiff_t>(sensor_begin), out.end(),
                       [](const SceneDetection& a, const SceneDetection& b) { return a.t_s < b.t_s; });
  }
  return out;
}

}  // namespace rnav::scene
