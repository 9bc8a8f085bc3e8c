#include "scripts/compose/scene/prl_validation.hpp"

#include "common/io/atomic_file.hpp"
#include "common/io/config.hpp"
#include "common/io/csv_columns.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "scripts/compose/export/prl_csv_recorder_node.hpp"
#include "sim/prl/prl_node.hpp"
#include "scripts/compose/scenario/prl_report.hpp"
#include "sim/trajectory/trajectory.hpp"
#include "sim/trajectory/trajectory_node.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace rnav {

namespace {

constexpr double kSiteToleranceM = 0.5;  ///< [m] the scenario's radar site against site.json's (rounding of x_m, z_m, height)

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// [s] the flight's median plot interval
double plot_interval_s(const PrlFlightData& f) {
  if (f.t_s.size() < 2) throw ConfigError("the flight has fewer than 2 radar plots");
  std::vector<double> dt;
  for (std::size_t i = 1; i < f.t_s.size(); ++i) dt.push_back(f.t_s[i] - f.t_s[i - 1]);
  return median(dt);
}

}  // namespace

SceneStats prl_flight_stats(const PrlFlightData& f) {
  const LocalLevelFrame R = f.radar_frame();
  std::vector<double> dr, da, de;
  std::size_t j = 0;
  for (std::size_t i = 0; i < f.t_s.size(); ++i) {
    const double t = f.t_s[i];
    while (j + 1 < f.nav.size() && f.nav[j + 1].t_s < t) ++j;
    if (f.nav.size() < 2 || t < f.nav.front().t_s || t > f.nav.back().t_s || j + 1 >= f.nav.size()) continue;  // outside the nav span
    const GeoSample &a = f.nav[j], &b = f.nav[j + 1];
    const double w = (t - a.t_s) / (b.t_s - a.t_s);
    // linear in the radar frame: p(t) = p_a + w (p_b - p_a)
    const Eigen::Vector3d pa = R.from_geodetic(a.g), pb = R.from_geodetic(b.g);
    const Polar pred = polar_from_cartesian(pa + w * (pb - pa));
    const Polar& q = f.plots[i];
    dr.push_back(q.range_m - pred.range_m);
    da.push_back(wrap_pi(q.course_rad - pred.course_rad));
    de.push_back(q.glide_rad - pred.glide_rad);
  }
  SceneStats s;
  const std::string pair = "radar:aircraft";
  s.residuals[pair + ":range"] = residual_stats(dr);
  s.residuals[pair + ":azimuth"] = residual_stats(da);
  s.residuals[pair + ":elevation"] = residual_stats(de);
  s.associated[pair] = static_cast<int>(dr.size());
  const double period = plot_interval_s(f);
  const double scans = std::floor((f.t_s.back() - f.t_s.front()) / period + 0.5) + 1;
  s.detection_rate[pair] = static_cast<double>(f.t_s.size()) / scans;
  return s;
}

Scenario scenario_of_flight(const PrlFlightData& f, Scenario sc, const std::string& work_dir) {
  if (f.nav.size() < 3) throw ConfigError("the flight's nav.csv has fewer than 3 samples: nothing to replay");
  sc.runway.threshold = f.threshold;
  sc.runway.heading_deg = f.heading_deg;
  const LocalLevelFrame L = sc.landing_frame();
  const Eigen::Vector3d p = L.from_geodetic(f.radar_site);
  sc.radar.x_m = p.x();
  sc.radar.z_m = p.z();
  sc.radar.antenna_height_m = f.radar_site.h_m - f.threshold.h_m;
  sc.radar.azimuth_reference_deg = f.azimuth_reference_deg;
  const double step = sc.trajectory.step_s;
  const double t0 = f.nav.front().t_s;
  // plot period and phase on the truth grid (the simulator's plots lie on it)
  sc.prl.period_s = std::max(step, std::round(plot_interval_s(f) / step) * step);
  sc.prl.phase_s = std::round(std::fmod(std::max(0.0, f.t_s.front() - t0), sc.prl.period_s) / step) * step;
  if (sc.prl.phase_s >= sc.prl.period_s) sc.prl.phase_s = 0;
  std::filesystem::create_directories(work_dir);
  const std::string csv = (std::filesystem::path(work_dir) / "replay.csv").string();
  {
    std::ostringstream o;
    o << "t_s,lat_deg,lon_deg,h_m\n" << std::fixed;
    for (const auto& s : f.nav)
      o << std::setprecision(6) << s.t_s - t0 << "," << std::setprecision(10) << s.g.lat_deg << "," << s.g.lon_deg << ","
        << std::setprecision(4) << s.g.h_m << "\n";
    std::ofstream out(csv);
    out << o.str();
    if (!out) throw ConfigError("cannot write " + csv);
  }
  sc.trajectory.replay_csv = csv;
  // the replay's smoothing window must hold 3 samples everywhere: at least twice the largest step
  double largest = 0;
  for (std::size_t i = 1; i < f.nav.size(); ++i) largest = std::max(largest, f.nav[i].t_s - f.nav[i - 1].t_s);
  sc.trajectory.replay_smoothing_s = std::max(sc.trajectory.replay_smoothing_s, 2.5 * largest);
  // re-read through the scenario's own checks (ranges of every key), then the site's placement
  nlohmann::json doc = nlohmann::json::parse(sc.json_text());
  doc["kind"] = "prl";
  try {
    sc = Scenario::from_json(doc);
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("the flight does not fit a landing scenario: ") + e.what());
  }
  const Eigen::Vector3d back = L.from_geodetic(sc.radar_site());
  if ((back - p).norm() > kSiteToleranceM)
    throw ConfigError("the flight's radar site cannot be placed in the scenario (" + value_text((back - p).norm()) + " m off)");
  return sc;
}

std::string write_flight_scenario(const Scenario& sc, const std::string& out_dir) {
  const std::filesystem::path dir(out_dir), csv = dir / "replay.csv";
  if (std::filesystem::absolute(sc.trajectory.replay_csv).lexically_normal() != std::filesystem::absolute(csv).lexically_normal())
    throw std::logic_error("write_flight_scenario: the scenario's replay_csv " + sc.trajectory.replay_csv + " is not " + csv.string());
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(sc.json_text());
  doc["kind"] = "prl";
  doc["trajectory"]["replay_csv"] = "replay.csv";
  const std::string file = (dir / "scenario.json").string();
  write_file_atomic(file, doc.dump(2) + "\n");
  return file;
}

Scenario extended_scenario(const PrlFlightData& f, Scenario sc, const nlohmann::json& report, const std::string& source) {
  sc.prl_effects = prl_effects_from_report(report, source);
  std::map<std::string, double> bias;
  if (report.contains("effects") && report["effects"].is_array())
    for (const auto& e : report["effects"])
      if (e.value("nominal", false) && e.contains("estimate") && e["estimate"].is_number())
        bias[e.value("name", "")] = e["estimate"].get<double>();
  for (const char* k : {"range_bias", "azimuth_bias", "elevation_bias"})
    if (!bias.count(k)) throw ConfigError(source + ": the report has no nominal " + std::string(k) + " estimate (a landing-radar report holds one)");
  // b_sim = b - d (t_first_plot - t_nav_start)
  const double lead_s = f.t_s.front() - f.nav.front().t_s;
  const PrlEffectsOptions& e = sc.prl_effects;
  sc.prl.bias_range_m = bias["range_bias"] - e.drift_range_mps * lead_s;
  sc.prl.bias_course_deg = (bias["azimuth_bias"] - e.drift_course_radps * lead_s) * 180 / M_PI;
  sc.prl.bias_glide_deg = (bias["elevation_bias"] - e.drift_glide_radps * lead_s) * 180 / M_PI;
  nlohmann::json doc = nlohmann::json::parse(sc.json_text());  // the scenario's own range checks
  try {
    return Scenario::from_json(doc);
  } catch (const ConfigError& x) {
    throw ConfigError(source + ": its effects do not fit a landing scenario: " + x.what());
  }
}

std::vector<SceneStats> simulated_flight_stats(const Scenario& sc, int runs, std::int64_t seed, const std::string& work_dir) {
  std::vector<SceneStats> out;
  const double duration = make_trajectory(sc.trajectory, sc.site())->duration_s();
  for (int k = 0; k < runs; ++k) {
    const std::string dir = (std::filesystem::path(work_dir) / ("sim_" + std::to_string(k))).string();
    InprocBus bus;
    std::vector<std::unique_ptr<LockstepNode>> nodes;
    nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc.trajectory, sc.site()));
    add_nav_nodes(bus, sc, nodes, "");
    nodes.push_back(std::make_unique<PrlNode>(bus, sc.prl, sc.prl_effects, sc.site()));
    nodes.push_back(std::make_unique<PrlCsvRecorderNode>(bus, sc, k, dir));
    ConductorOptions shard;  // realization k alone: the same as realization k of the whole ensemble
    shard.first_realization = k;
    const auto r = run_inproc_nodes(bus, nodes, sc.runner, sc.trajectory.step_s, duration, 1, seed, {}, shard);
    if (r.exit_code != 0) throw std::runtime_error("simulated flight " + std::to_string(k) + " failed: " + r.failure);
    out.push_back(prl_flight_stats(PrlFlightData::read_folder(dir)));
    std::filesystem::remove_all(dir);
  }
  return out;
}

}  // namespace rnav
