#include "estimators/diagnosis/reference_jumps.hpp"

#include "common/io/config.hpp"
#include "estimators/model_id/stats.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace rnav {

namespace {

constexpr std::size_t kMinChords = 5;      // fewer: no scatter to measure the bound against
constexpr double kMadToSd = 1.4826;        // sd of a Gaussian per median absolute deviation

// 1.4826 MAD: a robust sd, untouched by the few samples around a jump.
double robust_sd(const std::vector<double>& x) {
  const double m = median(x);
  std::vector<double> d;
  d.reserve(x.size());
  for (double v : x) d.push_back(std::abs(v - m));
  return kMadToSd * median(d);
}

struct Chord {
  std::size_t k;
  double lever_s2;     // (t_k - t_a)(t_b - t_k)
  Eigen::Vector2d e;   // deviation from the chord [m]
};

}  // namespace

ReferenceIntegrity check_reference_jumps(const std::vector<GeoSample>& v, const LocalLevelFrame& F,
                                         const ReferenceJumpOptions& o) {
  if (!(o.max_accel_mps2 > 0) || !std::isfinite(o.max_accel_mps2))
    throw ConfigError("reference jump check: max_accel_mps2 must be finite and > 0");
  if (!(o.half_span_s > 0) || !std::isfinite(o.half_span_s)) throw ConfigError("reference jump check: half_span_s must be finite and > 0");
  if (!(o.scatter_sigmas > 0) || !std::isfinite(o.scatter_sigmas))
    throw ConfigError("reference jump check: scatter_sigmas must be finite and > 0");
  if (!(o.max_gap_s > 0) || !std::isfinite(o.max_gap_s)) throw ConfigError("reference jump check: max_gap_s must be finite and > 0");
  ReferenceIntegrity out;
  out.samples = out.samples_used = v.size();
  if (!v.empty()) out.first_s = out.used_from_s = v.front().t_s, out.used_to_s = v.back().t_s;
  std::vector<Eigen::Vector2d> p;
  p.reserve(v.size());
  for (const auto& s : v) {
    const Eigen::Vector3d q = F.from_geodetic(s.g);
    p.emplace_back(q.x(), q.z());
  }
  // e_k = p_k - (p_a + (t_k - t_a) / (t_b - t_a) (p_b - p_a)), a and b half_span_s away (or more)
  std::vector<Chord> chords;
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    std::size_t a = k - 1, b = k + 1;
    while (a > 0 && v[k].t_s - v[a].t_s < o.half_span_s) --a;
    while (b + 1 < v.size() && v[b].t_s - v[k].t_s < o.half_span_s) ++b;
    const double ta = v[a].t_s, tk = v[k].t_s, tb = v[b].t_s;
    bool gap = false;
    for (std::size_t j = a; j < b && !gap; ++j) gap = v[j + 1].t_s - v[j].t_s > o.max_gap_s;
    if (gap || !(tb > ta)) continue;
    const double w = (tk - ta) / (tb - ta);
    chords.push_back({k, (tk - ta) * (tb - tk), p[k] - (p[a] + w * (p[b] - p[a]))});
  }
  if (chords.size() < kMinChords) return out;
  std::vector<double> north, east;
  for (const auto& c : chords) north.push_back(c.e.x()), east.push_back(c.e.y());
  const double scatter_m = std::max(robust_sd(north), robust_sd(east));
  // |e_k| > A (t_k - t_a)(t_b - t_k) / 2 + n_sigma s
  struct Flag {
    double t_s, ratio, deviation_m, bound_m;
  };
  std::vector<Flag> flags;
  for (const auto& c : chords) {
    const double bound = o.max_accel_mps2 * c.lever_s2 / 2 + o.scatter_sigmas * scatter_m;
    const double dev = c.e.norm();
    if (dev > bound) flags.push_back({v[c.k].t_s, dev / bound, dev, bound});
  }
  if (flags.empty()) return out;
  // flags within 2 half-spans of each other: one jump; untrusted from half a span before its
  // first flag to half a span after its last
  std::vector<std::pair<double, double>> untrusted;
  for (std::size_t i = 0; i < flags.size();) {
    std::size_t j = i, best = i;
    while (j + 1 < flags.size() && flags[j + 1].t_s - flags[j].t_s <= 2 * o.half_span_s) {
      ++j;
      if (flags[j].ratio > flags[best].ratio) best = j;
    }
    // a step at T flags the samples whose chords straddle it, about as many on either side
    out.jumps.push_back({(flags[i].t_s + flags[j].t_s) / 2, flags[best].deviation_m, flags[best].bound_m});
    untrusted.emplace_back(flags[i].t_s - o.half_span_s, flags[j].t_s + o.half_span_s);
    i = j + 1;
  }
  // the longest stretch between the untrusted spans (ties: the earliest)
  double from = v.front().t_s, best_len = 0;
  out.used_from_s = out.used_to_s = v.front().t_s;  // nothing usable unless a stretch is found
  auto consider = [&](double a, double b) {
    if (b - a > best_len) best_len = b - a, out.used_from_s = a, out.used_to_s = b;
  };
  for (const auto& [a, b] : untrusted) {
    consider(from, std::min(a, v.back().t_s));
    from = std::max(from, b);
  }
  consider(from, v.back().t_s);
  out.samples_used = best_len > 0 ? static_cast<std::size_t>(std::count_if(v.begin(), v.end(), [&](const GeoSample& s) {
    return s.t_s >= out.used_from_s && s.t_s <= out.used_to_s;
  })) : 0;
  return out;
}

std::vector<GeoSample> used_stretch(const std::vector<GeoSample>& v, const ReferenceIntegrity& ri) {
  std::vector<GeoSample> out;
  if (ri.samples_used == 0) return out;
  for (const auto& x : v)
    if (x.t_s >= ri.used_from_s && x.t_s <= ri.used_to_s) out.push_back(x);
  return out;
}

}  // namespace rnav
