#include "sim/scene/scene_sim.hpp"

#include "common/physics/frames.hpp"
#include "common/physics/multi_effect_columns.hpp"
#include "sim/scene/scene_geometry.hpp"

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

// A target's detection before its channel noise: the index into the output and its geometry.
struct Pending {
  std::size_t row;
  LineOfSight los;
};

}  // namespace

std::vector<SceneDetection> simulate(const RecordedScene& scene, const SceneErrors& errors, std::uint64_t seed,
                                     std::uint64_t realization) {
  scene.check();
  errors.check();
  std::vector<SceneDetection> out;
  for (const SceneSensor& s : scene.sensors) {
    std::mt19937_64 rng = stream(seed, realization, 1, s.name);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::poisson_distribution<int> clutter_count(s.clutter_per_scan > 0 ? s.clutter_per_scan : 1.0);
    std::map<std::string, std::vector<Pending>> by_target;  // detections awaiting their channel's noise
    std::size_t next_clutter = 0;                            // replayed clutter: the first not yet passed
    for (double t : s.scan_times_s) {
      bool any = false;
      for (const auto& [name, track] : scene.targets) {
        // one uniform per target and scan whatever happens, so that the streams stay aligned
        const double u = U(rng);
        const auto pd = s.p_detect.find(name);
        if (pd == s.p_detect.end() || !(u < pd->second)) continue;
        LineOfSight los;
        if (!line_of_sight(scene.observer, track, t, scene.reference_max_gap_s, los)) continue;
        if (!s.coverage.covers(los.bearing_rad, los.range_m)) continue;
        by_target[name].push_back({out.size(), los});
        out.push_back({t, s.name, s.ranged ? los.range_m : NAN, los.bearing_rad, name});
        any = true;
      }
      if (s.replay_clutter) {  // the recording's own returns of this scan
        for (; next_clutter < s.clutter.size() && s.clutter[next_clutter].t_s <= t; ++next_clutter) {
          if (s.clutter[next_clutter].t_s < t) continue;  // a return between scans: none here
          out.push_back({t, s.name, s.ranged ? s.clutter[next_clutter].range_m : NAN, s.clutter[next_clutter].bearing_rad, ""});
          any = true;
        }
      } else {
        const int n_clutter = s.clutter_per_scan > 0 ? clutter_count(rng) : 0;
        for (int k = 0; k < n_clutter; ++k) {
          const auto i = std::min(static_cast<std::size_t>(U(rng) * static_cast<double>(s.clutter.size())), s.clutter.size() - 1);
          out.push_back({t, s.name, s.ranged ? s.clutter[i].range_m : NAN, s.clutter[i].bearing_rad, ""});
          any = true;
        }
      }
      if (!any) out.push_back({t, s.name, NAN, NAN, ""});  // an empty scan keeps the scan count
    }
    // each channel: y = h + sum c theta + noise, the noise drawn over the channel's own times
    for (const auto& [name, list] : by_target) {
      for (const bool is_range : {false, true}) {
        if (is_range && !s.ranged) continue;
        const std::string ch = channel_name(s.name, name, is_range);
        std::vector<double> times;
        for (const auto& p : list) times.push_back(out[p.row].t_s);
        std::mt19937_64 nrng = stream(seed, realization, 2, ch);
        const Eigen::VectorXd noise = sample_noise(times, {}, errors.channel_noise(ch, is_range), nrng);
        for (std::size_t k = 0; k < list.size(); ++k) {
          SceneDetection& d = out[list[k].row];
          const multi_effect::Geometry g = effect_geometry(list[k].los, is_range, d.t_s, scene.min_speed_mps);
          const double dy = effects_at(errors, g, s.name, name, s.scan_period_s) + noise(static_cast<Eigen::Index>(k));
          if (is_range)
            d.range_m = std::max(d.range_m + dy, 0.0);
          else
            d.bearing_rad = wrap_pi(d.bearing_rad + dy);
        }
      }
    }
  }
  return out;
}

}  // namespace rnav::scene
