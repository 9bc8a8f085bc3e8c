// A recording of this test suite's own (the multi-sensor folder format): an observer on a
// straight course, two boats (one passing, one circling) with exact 1 Hz references, a rotating
// radar (2 s scans, 0.3 deg and 2 m white noise, p_d 0.9, one clutter return per scan) whose
// bearings may carry a hidden bias, and a camera (0.25 s frames, 0.2 deg, p_d 0.8). Shared by
// the scene tests (test_scene.cpp, test_scene_run.cpp).
#pragma once

#include "common/physics/frames.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"

#include <cmath>
#include <algorithm>
#include <random>
#include <vector>
#include <string>

namespace rnav_test::scene_gen {

using namespace rnav;

inline const LocalLevelFrame kFrame({63.43, 10.39, 0.0}, 0.0);

// (east, north) [m] -> geodetic, through the frame (x north, y up, z east).
inline Geodetic geo(const Eigen::Vector2d& en) { return kFrame.to_geodetic(Eigen::Vector3d(en.y(), 0, en.x())); }

inline Eigen::Vector2d own(double t) { return {0.5 * t, 0.8 * t}; }
inline Eigen::Vector2d boat(int k, double t) {
  if (k == 1) return {300 + 3 * t, 200 - 1.5 * t};  // 3.4 m/s, passing east of the observer
  const double w = 2 * M_PI / 240;                   // boat 2: a circle of 150 m about (-250, 300)
  return {-250 + 150 * std::cos(w * t), 300 + 150 * std::sin(w * t)};
}

inline constexpr double kRadarBiasRad = 1.5 * M_PI / 180;  // the hidden effect: the radar's bearings 1.5 deg off
inline constexpr double kDuration = 240;
inline constexpr double kBeamPeriodS = 2;                 // the radar's scan (rotation) period
inline constexpr double kBeamB0Rad = 0.7;                 // own_stamps: the beam's bearing at t = 0

// An independent recording: a radar (2 s scans, 0.3 deg and 2 m white noise, p_d 0.9) and a camera
// (0.25 s, 0.2 deg, p_d 0.8), a clutter return per radar scan, exact references at 1 Hz; every
// time stamp t0 [s] later (e.g. Unix seconds, as real recordings stamp).
inline MultiSensorData recording(std::uint64_t seed, double radar_bias_rad, double t0 = 0, bool own_stamps = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  std::uniform_real_distribution<double> U(0, 1);
  MultiSensorData d;
  for (double t = 0; t <= kDuration; t += 0.5) d.observer.push_back({t, geo(own(t))});
  d.observer_heading_deg.assign(d.observer.size(), NAN);
  for (int k = 1; k <= 2; ++k)
    for (double t = 0; t <= kDuration; t += 1) d.truth[std::to_string(k)].push_back({t, geo(boat(k, t))});
  // own_stamps: the beam turns clockwise from kBeamB0Rad at t = 0, period 2 s; each return is
  // stamped at the time it is lit, t = start + 2 s ((b - b0) mod 2 pi) / (2 pi), with b the
  // target's bearing then (a fixed point: three steps from the scan's start, the boats' bearings
  // moving by far less than the beam's 180 deg/s)
  const auto lit_at = [](double start, double bearing_rad) {
    const double b = bearing_rad - kBeamB0Rad;
    return start + kBeamPeriodS * (b - 2 * M_PI * std::floor(b / (2 * M_PI))) / (2 * M_PI);
  };
  const auto lit = [&](double start, int k) {
    double t = start;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d r = boat(k, t) - own(t);
      t = lit_at(start, std::atan2(r.x(), r.y()));
    }
    return t;
  };
  std::vector<Detection> radar;
  for (double t = 2; t < kDuration - 2; t += kBeamPeriodS) {
    for (int k = 1; k <= 2; ++k) {
      if (U(rng) > 0.9) continue;
      const double tk = own_stamps ? lit(t, k) : t;
      const Eigen::Vector2d r = boat(k, tk) - own(tk);
      radar.push_back({tk, "radar", r.norm() + 2 * N(rng), wrap_pi(std::atan2(r.x(), r.y()) + radar_bias_rad + 0.3 * kDegToRad * N(rng)), NAN});
    }
    const double rc = 100 + 900 * U(rng);
    const double b = wrap_pi(2 * M_PI * U(rng));
    radar.push_back({own_stamps ? lit_at(t, b) : t, "radar", rc, b, NAN});
  }
  std::stable_sort(radar.begin(), radar.end(), [](const Detection& a, const Detection& b) { return a.t_s < b.t_s; });
  d.detections = radar;
  for (double t = 2; t < kDuration - 2; t += 0.25)
    for (int k = 1; k <= 2; ++k) {
      if (U(rng) > 0.8) continue;
      const Eigen::Vector2d r = boat(k, t) - own(t);
      d.detections.push_back({t, "eo", NAN, wrap_pi(std::atan2(r.x(), r.y()) + 0.2 * kDegToRad * N(rng)), NAN});
    }
  if (t0 != 0) {
    for (auto& x : d.observer) x.t_s += t0;
    for (auto& [_, tr] : d.truth)
      for (auto& x : tr) x.t_s += t0;
    for (auto& x : d.detections) x.t_s += t0;
  }
  return d;
}

}  // namespace rnav_test::scene_gen
