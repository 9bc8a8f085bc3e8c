#include "multi_problem.hpp"

#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>

namespace rnav {

namespace {

// Per observation: the geometry the columns need.
struct ObsGeom {
  bool is_range = false;
  std::string sensor, target;
  Eigen::RowVector2d dh;          ///< d h / d d
  Eigen::Vector2d v_rel, v_target, u, u_perp;
  double range_pred = 0, t = 0;
};
using Geoms = std::shared_ptr<const std::vector<ObsGeom>>;

// A column set from a per-observation function (k columns); zero where `in` is false.
template <class In, class Val>
std::function<Eigen::MatrixXd(std::size_t)> cols(const Geoms& g, int k, In in, Val val) {
  return [g, k, in, val](std::size_t v) {
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(g->size()), k);
    for (std::size_t i = 0; i < g->size(); ++i)
      if (in((*g)[i])) C.row(static_cast<Eigen::Index>(i)) = val((*g)[i], v);
    return C;
  };
}

Eigen::RowVectorXd one(double x) { return Eigen::RowVectorXd::Constant(1, x); }

}  // namespace

MultiProblem build_multi_problem(const std::vector<AssociatedDetection>& a, double sb, double sr, double split_fraction,
                                 int step_grid) {
  if (!(sb > 0 && sr > 0)) throw ConfigError("multi diagnosis: nominal sigmas must be > 0");
  if (!(split_fraction > 0.2 && split_fraction < 0.9)) throw ConfigError("multi diagnosis: split fraction must be in (0.2, 0.9)");
  if (step_grid < 2) throw ConfigError("multi diagnosis: step grid must be >= 2");
  MultiProblem mp;
  Problem& p = mp.problem;
  if (a.empty()) throw ConfigError("multi diagnosis: no detection associated to any target");
  double t0 = a.front().t_s, t1 = t0;
  for (const auto& x : a) t0 = std::min(t0, x.t_s), t1 = std::max(t1, x.t_s);
  mp.split_time_s = t0 + split_fraction * (t1 - t0);

  // channels in a fixed order: sensor, target, quantity
  std::map<std::string, std::vector<std::pair<std::size_t, bool>>> by_channel;  // name -> (assoc index, is_range)
  std::map<std::string, Channel> channel_of;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto& x = a[i];
    const std::string base = x.sensor + ":" + x.target;
    by_channel[base + ":bearing"].push_back({i, false});
    channel_of[base + ":bearing"] = {base + ":bearing", x.sensor, x.target, "rad", sb};
    if (x.has_range) {
      by_channel[base + ":range"].push_back({i, true});
      channel_of[base + ":range"] = {base + ":range", x.sensor, x.target, "m", sr};
    }
  }
  mp.bearing_obs.assign(a.size(), -1);
  mp.range_obs.assign(a.size(), -1);
  auto geoms = std::make_shared<std::vector<ObsGeom>>();
  for (auto& [name, list] : by_channel) {
    if (list.size() < 10) {  // too few to identify a noise model: reported, not used
      mp.dropped_channels.push_back(name + " (" + std::to_string(list.size()) + " detections)");
      continue;
    }
    std::stable_sort(list.begin(), list.end(), [&](const auto& u, const auto& w) { return a[u.first].t_s < a[w.first].t_s; });
    const int ch = static_cast<int>(p.channels.size());
    p.channels.push_back(channel_of[name]);
    for (const auto& [i, is_range] : list) {
      const auto& x = a[i];
      ObsGeom g;
      g.is_range = is_range;
      g.sensor = x.sensor;
      g.target = x.target;
      g.dh = is_range ? x.drange() : x.dbearing();
      g.v_rel = x.v_rel;
      g.v_target = x.v_target;
      g.u = x.u_course;
      g.u_perp = Eigen::Vector2d(-x.u_course.y(), x.u_course.x());
      g.range_pred = x.range_pred();
      g.t = x.t_s;
      (is_range ? mp.range_obs : mp.bearing_obs)[i] = static_cast<long>(p.y.size());
      p.channel.push_back(ch);
      p.t_s.push_back(x.t_s);
      p.y.push_back(is_range ? x.range_m - x.range_pred() : wrap_pi(x.bearing_rad - x.bearing_pred()));
      p.estimation.push_back(x.t_s < mp.split_time_s);
      geoms->push_back(g);
    }
  }
  if (p.channels.empty()) throw ConfigError("multi diagnosis: no sensor:target pair with 10 or more associated detections");
  const auto n = static_cast<Eigen::Index>(p.y.size());
  p.nuisance = Eigen::MatrixXd(n, 0);
  const Geoms G = geoms;

  std::set<std::string> sensors, targets, range_sensors;
  for (const auto& c : p.channels) {
    sensors.insert(c.sensor);
    targets.insert(c.target);
    if (c.unit == "m") range_sensors.insert(c.sensor);
  }
  auto add = [&](Candidate c) {
    p.catalogue.push_back(std::move(c));
    return p.catalogue.size() - 1;
  };
  std::vector<std::size_t> sensor_clock, target_clock, sensor_bias, pair_offset, target_offset;
  std::size_t common_clock = 0, common_bias = 0;
  const std::string rate_sig = "the rate of the sensor's measurement (target and observer motion)";
  for (const auto& s : sensors) {
    auto is_s = [s](const ObsGeom& g) { return g.sensor == s; };
    sensor_clock.push_back(add({"time_offset", {s, ""}, {"s"}, rate_sig, "", {},
                                cols(G, 1, is_s, [](const ObsGeom& g, std::size_t) { return one(-g.dh * g.v_rel); })}));
    sensor_bias.push_back(add({"bearing_bias", {s, ""}, {"rad"}, "a constant on this sensor's bearings", "", {},
                               cols(G, 1, [s](const ObsGeom& g) { return g.sensor == s && !g.is_range; },
                                    [](const ObsGeom&, std::size_t) { return one(1.0); })}));
    std::vector<double> grid;
    for (int k = 0; k < step_grid; ++k) grid.push_back(t0 + (t1 - t0) * (0.1 + 0.8 * k / (step_grid - 1)));
    add({"bias_step", {s, ""}, {"rad"}, "a jump in this sensor's bearings at one time", "t_s", grid,
         cols(G, 1, [s](const ObsGeom& g) { return g.sensor == s && !g.is_range; },
              [grid](const ObsGeom& g, std::size_t v) { return one(g.t >= grid[v] ? 1.0 : 0.0); })});
  }
  for (const auto& s : range_sensors) {
    auto is_sr = [s](const ObsGeom& g) { return g.sensor == s && g.is_range; };
    add({"range_bias", {s, ""}, {"m"}, "a constant on this sensor's ranges", "", {},
         cols(G, 1, is_sr, [](const ObsGeom&, std::size_t) { return one(1.0); })});
    add({"range_gain", {s, ""}, {"1"}, "the range", "", {},
         cols(G, 1, is_sr, [](const ObsGeom& g, std::size_t) { return one(g.range_pred); })});
  }
  auto offset_cols = [](const ObsGeom& g, std::size_t) {
    Eigen::RowVectorXd r(2);
    r << g.dh * g.u, g.dh * g.u_perp;
    return r;
  };
  const std::string off_sig = "the line-of-sight component of the target's heading (aspect)";
  for (const auto& t : targets) {
    auto is_t = [t](const ObsGeom& g) { return g.target == t; };
    target_clock.push_back(add({"truth_time_offset", {"", t}, {"s"},
                                "the rate due to the target's own motion (the same for every sensor)", "", {},
                                cols(G, 1, is_t, [](const ObsGeom& g, std::size_t) { return one(g.dh * g.v_target); })}));
    target_offset.push_back(add({"antenna_offset", {"", t}, {"along_m", "starboard_m"}, off_sig, "", {},
                                 cols(G, 2, is_t, offset_cols)}));
    for (const auto& s : range_sensors)
      pair_offset.push_back(add({"antenna_offset", {s, t}, {"along_m", "starboard_m"}, off_sig + " seen by " + s, "", {},
                                 cols(G, 2, [s, t](const ObsGeom& g) { return g.sensor == s && g.target == t; }, offset_cols)}));
  }
  if (sensors.size() > 1) {
    common_clock = add({"time_offset", {"", ""}, {"s"}, "the rate of every sensor's measurement (one clock)", "", {},
                        cols(G, 1, [](const ObsGeom&) { return true; },
                             [](const ObsGeom& g, std::size_t) { return one(-g.dh * g.v_rel); })});
    common_bias = add({"bearing_bias", {"", ""}, {"rad"}, "a constant on every sensor's bearings (the observer's heading)", "", {},
                       cols(G, 1, [](const ObsGeom& g) { return !g.is_range; },
                            [](const ObsGeom&, std::size_t) { return one(1.0); })});
  }

  // scope questions
  ScopeQuestion clock{"which clock is off: the sensors', the targets' references', both, or one common clock?", {}};
  clock.alternatives.push_back({"per sensor", sensor_clock});
  clock.alternatives.push_back({"per target reference", target_clock});
  std::vector<std::size_t> both = sensor_clock;
  both.insert(both.end(), target_clock.begin(), target_clock.end());
  clock.alternatives.push_back({"per sensor and per target", both});
  if (sensors.size() > 1) clock.alternatives.push_back({"one common clock", {common_clock}});
  p.scope_questions.push_back(clock);
  if (sensors.size() > 1)
    p.scope_questions.push_back({"bearing bias: per sensor, or the observer's heading (common)?",
                                 {{"per sensor", sensor_bias}, {"common (heading)", {common_bias}}}});
  if (!pair_offset.empty())
    p.scope_questions.push_back({"hull offset: per target (antenna) or per sensor and target (where each sensor sees the hull)?",
                                 {{"per target", target_offset}, {"per sensor and target", pair_offset}}});

  // covariates for what stays unexplained
  std::vector<double> range(static_cast<std::size_t>(n)), aspect(static_cast<std::size_t>(n)), speed(static_cast<std::size_t>(n)),
      time(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < G->size(); ++i) {
    const auto& g = (*G)[i];
    range[i] = g.range_pred;
    speed[i] = g.v_target.norm();
    time[i] = g.t - t0;
    aspect[i] = g.dh * g.u_perp;  // the line-of-sight cross-component of the hull axis
  }
  p.covariates = {{"range", range}, {"target speed", speed}, {"time", time}, {"aspect (hull across the line of sight)", aspect}};
  return mp;
}

}  // namespace rnav
