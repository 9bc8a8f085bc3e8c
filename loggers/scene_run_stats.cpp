#include "loggers/scene_run_stats.hpp"

#include "common/io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

namespace rnav {

std::vector<scene::SceneDetection> SceneRealization::detections() const {
  std::vector<scene::SceneDetection> all;
  for (const auto& s : by_sensor) all.insert(all.end(), s.begin(), s.end());
  return all;
}

SceneCounts scene_counts(const SceneRealization& r) {
  SceneCounts c;
  for (const auto& rows : r.by_sensor) {
    std::set<double> scans;
    for (const auto& d : rows) {
      auto& k = c[d.sensor];
      scans.insert(d.t_s);
      if (std::isnan(d.bearing_rad)) continue;  // an empty scan
      ++k["detections"];
      if (d.target.empty())
        ++k["clutter"];
      else
        ++k["target:" + d.target];
    }
    if (!rows.empty()) c[rows.front().sensor]["scans"] = static_cast<long>(scans.size());
  }
  return c;
}

SceneRunStats::SceneRunStats(std::string recording, std::vector<std::string> sensors, std::vector<std::string> targets)
    : recording_(std::move(recording)), sensors_(std::move(sensors)), targets_(std::move(targets)) {}

namespace {
std::vector<std::string> count_names(const std::vector<std::string>& targets) {
  std::vector<std::string> n{"scans", "detections", "clutter"};
  for (const auto& t : targets) n.push_back("target:" + t);
  return n;
}
}  // namespace

void SceneRunStats::add_realization(const SceneRealization& r, long) {
  const SceneCounts c = scene_counts(r);
  for (const auto& s : sensors_)
    for (const auto& name : count_names(targets_)) {
      long x = 0;
      if (auto i = c.find(s); i != c.end())
        if (auto j = i->second.find(name); j != i->second.end()) x = j->second;
      auto& [sum, sum2] = sums_[s][name];
      sum += static_cast<double>(x);
      sum2 += static_cast<double>(x) * static_cast<double>(x);
    }
  ++n_;
}

std::pair<double, double> SceneRunStats::mean_sd(const std::string& sensor, const std::string& count) const {
  if (n_ == 0) return {0, 0};
  const auto i = sums_.find(sensor);
  if (i == sums_.end()) return {0, 0};
  const auto j = i->second.find(count);
  if (j == i->second.end()) return {0, 0};
  const double n = static_cast<double>(n_), m = j->second.first / n;
  // sample standard deviation: (sum x^2 - n m^2) / (n - 1)
  const double var = n_ > 1 ? std::max(0.0, (j->second.second - n * m * m) / (n - 1)) : 0.0;
  return {m, std::sqrt(var)};
}

void SceneRunStats::write(const std::string& dir, std::int64_t seed) const {
  nlohmann::ordered_json j;
  j["kind"] = "scene";
  j["recording"] = recording_;
  j["realizations"] = n_;
  j["seed"] = seed;
  j["units"] = "counts per realization: mean and sample standard deviation over the realizations";
  std::ostringstream txt;
  txt << "scene " << recording_ << ": " << n_ << " realization(s), seed " << seed << "; per realization, mean (sd)\n";
  char line[200];
  std::snprintf(line, sizeof line, "  %-12s %-24s %14s %12s\n", "sensor", "count", "mean", "sd");
  txt << line;
  for (const auto& s : sensors_) {
    nlohmann::ordered_json js;
    for (const auto& name : count_names(targets_)) {
      const auto [m, sd] = mean_sd(s, name);
      js[name] = {{"mean", m}, {"sd", sd}};
      std::snprintf(line, sizeof line, "  %-12s %-24s %14.2f %12.2f\n", s.c_str(), name.c_str(), m, sd);
      txt << line;
    }
    j["sensors"][s] = js;
  }
  write_file_atomic(dir, "summary.json", j.dump(1) + "\n");
  write_file_atomic(dir, "summary.txt", txt.str());
}

}  // namespace rnav
