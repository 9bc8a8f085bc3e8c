#include "scripts/compose/scene/scene_validation.hpp"

#include "common/physics/frames.hpp"
#include "scripts/compose/scene/scene_from_recording.hpp"
#include "sim/scene/scene_sim.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace rnav {

namespace {

PairQuantityStats stats_of(std::vector<std::pair<double, double>> tx) {  // (t, residual)
  std::stable_sort(tx.begin(), tx.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<double> x;
  for (const auto& p : tx) x.push_back(p.second);
  return residual_stats(x);
}

// The q-quantile of sorted finite values, linear between order statistics.
double quantile(const std::vector<double>& v, double q) {
  const double h = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

ValidationRow row_of(const std::string& rec, const std::string& model, const std::string& pair, const std::string& quantity,
                     const std::string& statistic, int n, double real, std::vector<double> sim) {
  ValidationRow r{rec, pair, quantity, statistic, model, n, real, NAN, NAN, NAN, false};
  std::vector<double> v;
  for (double x : sim)
    if (std::isfinite(x)) v.push_back(x);
  if (v.empty() || 2 * v.size() < sim.size() || !std::isfinite(real)) return r;
  std::sort(v.begin(), v.end());
  r.band_lo = quantile(v, 0.05);
  r.band_hi = quantile(v, 0.95);
  double below = 0;
  for (double x : v) below += x < real ? 1.0 : x == real ? 0.5 : 0.0;
  r.rank = below / static_cast<double>(v.size());
  r.inside = real >= r.band_lo && real <= r.band_hi;
  return r;
}

}  // namespace

PairQuantityStats residual_stats(const std::vector<double>& x) {
  PairQuantityStats s;
  s.n = static_cast<int>(x.size());
  if (s.n < 1) return s;
  double m = 0;
  for (double v : x) m += v;
  m /= s.n;
  s.mean = m;
  if (s.n < 3) return s;
  double ss = 0, c1 = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    ss += (x[i] - m) * (x[i] - m);
    if (i + 1 < x.size()) c1 += (x[i] - m) * (x[i + 1] - m);
  }
  s.sd = std::sqrt(ss / (s.n - 1));
  s.lag1 = ss > 0 ? c1 / ss : NAN;
  return s;
}

SceneStats scene_stats(const MultiSensorData& d, const AssociationOptions& o) {
  std::map<std::string, SensorAssociation> st;
  const auto a = associate(d, o, st);
  std::map<std::string, std::vector<std::pair<double, double>>> res;
  SceneStats s;
  for (const auto& x : a) {
    const std::string pair = x.sensor + ":" + x.target;
    res[pair + ":bearing"].push_back({x.t_s, wrap_pi(x.bearing_rad - x.bearing_pred())});
    if (x.has_range) res[pair + ":range"].push_back({x.t_s, x.range_m - x.range_pred()});
    ++s.associated[pair];
  }
  for (auto& [k, v] : res) s.residuals[k] = stats_of(std::move(v));
  for (const auto& [sensor, sa] : st)
    for (const auto& [t, _] : d.truth) {
      const auto it = sa.associated.find(t);
      s.detection_rate[sensor + ":" + t] = sa.scans > 0 ? (it == sa.associated.end() ? 0.0 : it->second) / static_cast<double>(sa.scans) : NAN;
    }
  return s;
}

std::vector<ValidationRow> validation_rows(const std::string& recording, const std::string& model, const SceneStats& real,
                                           const std::vector<SceneStats>& sims) {
  std::vector<ValidationRow> rows;
  for (const auto& [pair, rate] : real.detection_rate) {
    const auto na = real.associated.find(pair);
    const int n = na == real.associated.end() ? 0 : na->second;
    if (n == 0) continue;  // a target this sensor never detects: nothing to compare
    // its quantities: bearing and range first (the multi-sensor pairs), then any other the
    // statistics hold (a landing radar's azimuth and elevation), in name order
    std::vector<std::string> quantities{"bearing", "range"};
    for (auto it = real.residuals.lower_bound(pair + ":"); it != real.residuals.end() && it->first.rfind(pair + ":", 0) == 0; ++it) {
      const std::string q = it->first.substr(pair.size() + 1);
      if (std::find(quantities.begin(), quantities.end(), q) == quantities.end()) quantities.push_back(q);
    }
    for (const std::string& q : quantities) {
      const auto it = real.residuals.find(pair + ":" + q);
      if (it == real.residuals.end()) continue;
      const PairQuantityStats& r = it->second;
      std::vector<double> m, sd, l1;
      for (const auto& s : sims) {
        const auto jt = s.residuals.find(pair + ":" + q);
        const PairQuantityStats x = jt == s.residuals.end() ? PairQuantityStats{} : jt->second;
        m.push_back(x.mean), sd.push_back(x.sd), l1.push_back(x.lag1);
      }
      rows.push_back(row_of(recording, model, pair, q, "mean", n, r.mean, m));
      rows.push_back(row_of(recording, model, pair, q, "sd", n, r.sd, sd));
      rows.push_back(row_of(recording, model, pair, q, "lag1", n, r.lag1, l1));
    }
    std::vector<double> dr;
    for (const auto& s : sims) {
      const auto jt = s.detection_rate.find(pair);
      dr.push_back(jt == s.detection_rate.end() ? 0.0 : jt->second);
    }
    rows.push_back(row_of(recording, model, pair, "detection", "detection_rate", n, rate, dr));
  }
  return rows;
}

std::vector<SceneStats> simulated_stats(const MultiSensorData& real, const scene::RecordedScene& scene, const scene::SceneErrors& errors,
                                        const AssociationOptions& o, int runs, std::uint64_t seed, int threads) {
  std::vector<SceneStats> out(static_cast<std::size_t>(std::max(runs, 0)));
  std::vector<std::exception_ptr> err(static_cast<std::size_t>(std::max(threads, 1)));
  auto work = [&](int w) {
    try {
      for (int k = w; k < runs; k += threads)
        out[static_cast<std::size_t>(k)] = scene_stats(recording_of(real, scene::simulate(scene, errors, seed, static_cast<std::uint64_t>(k))), o);
    } catch (...) {
      err[static_cast<std::size_t>(w)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& e : err)
    if (e) std::rethrow_exception(e);
  return out;
}

nlohmann::ordered_json rows_json(const std::vector<ValidationRow>& rows) {
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(); };
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const auto& r : rows)
    j.push_back({{"recording", r.recording}, {"pair", r.pair}, {"quantity", r.quantity}, {"statistic", r.statistic}, {"model", r.model},
                 {"n", r.n}, {"real", num(r.real)}, {"band_lo", num(r.band_lo)}, {"band_hi", num(r.band_hi)}, {"rank", num(r.rank)},
                 {"inside", r.inside}});
  return j;
}

}  // namespace rnav
