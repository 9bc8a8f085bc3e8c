#include "estimators/diagnosis/multi_problem.hpp"

#include "common/io/config.hpp"
#include "common/physics/multi_effect_columns.hpp"
#include "common/physics/scan_stamp.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

namespace rnav {

namespace {

// An offset breaks its physical bound when its estimate does (0 standard errors of margin): on
// 15-minute harbour recordings a margin of 2 SE let a 55 +- 10 m starboard offset stand on a
// 35 m beam, and a 12 s reference clock (the echo's place along a long hull) stand.
constexpr double kHullBoundSe = 0;

// Per observation: the geometry the columns need (common/physics/multi_effect_columns.hpp) and its
// channel's recording, sensor and target.
struct ObsGeom : multi_effect::Geometry {
  int rec = 0;                    ///< recording index
  std::string sensor, target;
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

// True if some observation satisfies `in`.
template <class In>
bool any(const Geoms& g, In in) {
  return std::any_of(g->begin(), g->end(), in);
}

// printf into a string of whatever length it needs (the bounds' explanations below).
__attribute__((format(printf, 1, 2))) std::string printf_string(const char* fmt, ...) {
  va_list a, b;
  va_start(a, fmt);
  va_copy(b, a);
  const int n = std::vsnprintf(nullptr, 0, fmt, a);
  va_end(a);
  std::string out(static_cast<std::size_t>(std::max(n, 0)) + 1, '\0');
  std::vsnprintf(out.data(), out.size(), fmt, b);
  va_end(b);
  out.resize(static_cast<std::size_t>(std::max(n, 0)));
  return out;
}

std::string period_text(double T) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", T);
  return b;
}

// The reference's interpolation error (AssociatedDetection::ref_interp_sd_m, seen by a range as
// sd and by a bearing as sd / range) as each channel's nominal correlated component: sigma =
// its RMS over the channel's detections, seen with the gain sd_i / sigma (0 at a reference
// sample, largest mid-interval), correlation time the channel's median reference interval (one
// acceleration bends the whole interval). Only where sigma reaches kInterpolationFloor of the
// channel's nominal sigma: below, it changes the variance by under 1 %, and a reference at 1 Hz
// or faster (the Autoferry GNSS tracks) stays exact.
constexpr double kInterpolationFloor = 0.1;

void add_interpolation_noise(Problem& p, const std::vector<double>& sd, const std::vector<double>& interval) {
  std::vector<double> gain(p.size(), 1.0);
  bool any = false;
  std::vector<std::vector<std::size_t>> by_channel(p.channels.size());  // observations per channel, one pass
  for (std::size_t i = 0; i < p.size(); ++i) by_channel[static_cast<std::size_t>(p.channel[i])].push_back(i);
  for (std::size_t c = 0; c < p.channels.size(); ++c) {
    const std::vector<std::size_t>& obs = by_channel[c];
    double s2 = 0;
    std::vector<double> iv;
    for (std::size_t i : obs) s2 += sd[i] * sd[i], iv.push_back(interval[i]);
    const double rms = std::sqrt(s2 / static_cast<double>(obs.size()));
    Channel& ch = p.channels[c];
    if (!(rms >= kInterpolationFloor * ch.nominal_sigma)) continue;
    std::nth_element(iv.begin(), iv.begin() + static_cast<std::ptrdiff_t>(iv.size() / 2), iv.end());
    ch.nominal_corr_sigma = rms;
    ch.nominal_corr_tau_s = std::max(iv[iv.size() / 2], 1e-3);
    for (std::size_t i : obs) gain[i] = sd[i] / rms;
    any = true;
  }
  if (any) p.nominal_corr_gain = std::move(gain);
}

// Checks the options and the recordings' names; throws ConfigError naming the first fault.
void check_inputs(const std::vector<RecordingDetections>& recs, const MultiProblemOptions& o) {
  const double sb = o.sigma_bearing_rad, sr = o.sigma_range_m;
  if (!(sb > 0 && sr > 0)) throw ConfigError("multi diagnosis: nominal sigmas must be > 0");
  if (!(o.split_fraction > 0.2 && o.split_fraction < 0.9)) throw ConfigError("multi diagnosis: split fraction must be in (0.2, 0.9)");
  if (o.step_grid < 2 || o.sweep_grid < 2) throw ConfigError("multi diagnosis: step and sweep grids must be >= 2");
  if (!(o.min_sweep_period_s > 0)) throw ConfigError("multi diagnosis: min_sweep_period_s must be > 0");
  if (!(o.max_hull_length_m > 0 && o.max_hull_beam_m > 0) || !std::isfinite(o.max_hull_length_m) || !std::isfinite(o.max_hull_beam_m))
    throw ConfigError("multi diagnosis: the largest hull's length and beam must be finite and > 0");
  if (!(o.max_reference_clock_s > 0) || !std::isfinite(o.max_reference_clock_s))
    throw ConfigError("multi diagnosis: max_reference_clock_s must be finite and > 0");
  if (recs.empty()) throw ConfigError("multi diagnosis: no recording");
  const bool pooled = recs.size() > 1;
  std::set<std::string> names;
  for (const auto& r : recs)
    if (pooled && (r.name.empty() || !names.insert(r.name).second))
      throw ConfigError("multi diagnosis: recordings need distinct, non-empty names ('" + r.name + "' repeats or is empty)");
}

// Each recording's span [t0, t1] of detection times [s] and its split time (into mp), and the
// range sensors' scan periods (checked, into mp).
void set_spans(const std::vector<RecordingDetections>& recs, const MultiProblemOptions& o, MultiProblem& mp,
               std::vector<double>& t0, std::vector<double>& t1) {
  const bool pooled = recs.size() > 1;
  const int R = static_cast<int>(recs.size());
  for (int r = 0; r < R; ++r) {
    const auto& a = recs[static_cast<std::size_t>(r)].a;
    if (a.empty()) throw ConfigError("multi diagnosis: no detection associated to any target" + (pooled ? " in recording " + recs[static_cast<std::size_t>(r)].name : std::string()));
    t0[r] = t1[r] = a.front().t_s;
    for (const auto& x : a) t0[r] = std::min(t0[r], x.t_s), t1[r] = std::max(t1[r], x.t_s);
    mp.split_time_s.push_back(t0[r] + o.split_fraction * (t1[r] - t0[r]));
  }
  // each range sensor's scan period, as the caller measured it (MultiProblemOptions::scan_period_s)
  for (const auto& [s, T] : o.scan_period_s)
    if (!(T > 0) || !std::isfinite(T)) throw ConfigError("multi diagnosis: scan period of " + s + " must be finite and > 0");
  mp.scan_period_s = o.scan_period_s;
}

// Per observation, beside the problem's own rows: the geometry the columns need, the
// reference's interpolation sd [unit] and its interval [s].
struct ObsTables {
  std::vector<ObsGeom> geoms;
  std::vector<double> interp_sd, interval;
};

// The geometry of detection x of recording r, as a range or as a bearing observation.
ObsGeom geom_of(const AssociatedDetection& x, int r, bool is_range) {
  ObsGeom g;
  g.is_range = is_range;
  g.rec = r;
  g.sensor = x.sensor;
  g.target = x.target;
  g.dh = is_range ? x.drange() : x.dbearing();
  g.v_rel = x.v_rel;
  g.v_target = x.v_target;
  g.u = x.u_course;
  g.u_perp = Eigen::Vector2d(-x.u_course.y(), x.u_course.x());
  g.range_pred = x.range_pred();
  g.bearing_pred = x.bearing_pred();
  g.t = x.t_s;
  return g;
}

// Recording r's channels (sensor, target, quantity, in name order) with their observations in
// time order, appended to mp and obs; a channel of fewer than 10 detections is dropped.
void add_recording(const std::vector<RecordingDetections>& recs, int r, const MultiProblemOptions& o, MultiProblem& mp,
                   ObsTables& obs) {
  const double sb = o.sigma_bearing_rad, sr = o.sigma_range_m;
  const bool pooled = recs.size() > 1;
  Problem& p = mp.problem;
  const auto& rd = recs[static_cast<std::size_t>(r)];
  const auto& a = rd.a;
  const std::string prefix = pooled ? rd.name + "/" : "";
  std::map<std::string, std::vector<std::pair<std::size_t, bool>>> by_channel;  // name -> (assoc index, is_range)
  std::map<std::string, Channel> channel_of;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto& x = a[i];
    const std::string base = prefix + x.sensor + ":" + x.target;
    by_channel[base + ":bearing"].push_back({i, false});
    channel_of[base + ":bearing"] = {base + ":bearing", x.sensor, x.target, "rad", sb};
    channel_of[base + ":bearing"].offset_group = prefix + x.sensor + ":bearing";
    if (x.has_range) {
      by_channel[base + ":range"].push_back({i, true});
      channel_of[base + ":range"] = {base + ":range", x.sensor, x.target, "m", sr};
      channel_of[base + ":range"].offset_group = prefix + x.sensor + ":range";
    }
  }
  mp.bearing_obs.emplace_back(a.size(), -1);
  mp.range_obs.emplace_back(a.size(), -1);
  for (auto& [name, list] : by_channel) {
    if (list.size() < static_cast<std::size_t>(kMinPairDetections)) {  // too few to identify a noise model: reported, not used
      mp.dropped_channels.push_back(name + " (" + std::to_string(list.size()) + " detections)");
      continue;
    }
    std::stable_sort(list.begin(), list.end(), [&](const auto& u, const auto& w) { return a[u.first].t_s < a[w.first].t_s; });
    const int ch = static_cast<int>(p.channels.size());
    p.channels.push_back(channel_of[name]);
    for (const auto& [i, is_range] : list) {
      const auto& x = a[i];
      (is_range ? mp.range_obs : mp.bearing_obs).back()[i] = static_cast<long>(p.y.size());
      p.channel.push_back(ch);
      p.t_s.push_back(x.t_s);
      p.y.push_back(is_range ? x.range_m - x.range_pred() : wrap_pi(x.bearing_rad - x.bearing_pred()));
      p.estimation.push_back(x.t_s < mp.split_time_s[static_cast<std::size_t>(r)]);
      obs.geoms.push_back(geom_of(x, r, is_range));
      obs.interp_sd.push_back(is_range ? x.ref_interp_sd_m : x.ref_interp_sd_m / x.range_pred());
      obs.interval.push_back(x.ref_interval_s);
    }
  }
}

// The column of a clock offset: the rate of the sensor's measurement.
Eigen::RowVectorXd rate_column(const ObsGeom& g, std::size_t) { return multi_effect::sensor_clock(g); }

// The column of a constant.
Eigen::RowVectorXd unit_column(const ObsGeom& g, std::size_t) { return multi_effect::constant(g); }

using In = std::function<bool(const ObsGeom&)>;
using Val = std::function<Eigen::RowVectorXd(const ObsGeom&, std::size_t)>;

// The catalogue of a multi-sensor problem and its scope questions, built kind by kind into
// p.catalogue and p.scope_questions.
struct CatalogueBuilder {
  struct Kind {
    std::vector<std::size_t> hardware, per_recording;
  };

  CatalogueBuilder(MultiProblem& mp_in, const std::vector<RecordingDetections>& recs_in, const MultiProblemOptions& o_in,
                   const std::vector<double>& t0_in, const std::vector<double>& t1_in, Geoms G_in)
      : mp(mp_in), p(mp_in.problem), recs(recs_in), o(o_in), t0(t0_in), t1(t1_in), G(std::move(G_in)),
        pooled(recs_in.size() > 1), R(static_cast<int>(recs_in.size())) {
    for (const auto& c : p.channels) {
      sensors.insert(c.sensor);
      targets.insert(c.target);
      if (c.unit == "m") range_sensors.insert(c.sensor);
    }
  }

  // Appends c to the catalogue; returns its index.
  std::size_t add(Candidate c) {
    p.catalogue.push_back(std::move(c));
    return p.catalogue.size() - 1;
  }

  // A hardware entry (one value in every recording) and, pooled, its per-recording copies: the
  // alternative of its scope question and its replicates (replication.hpp); scope_only unless
  // `own` (an effect a recording may have of its own, e.g. a start-up bias: then each copy is a
  // candidate too). `in` selects the entry's observations.
  std::size_t hardware(const std::string& kind, Candidate c, int k, const In& in, const Val& val, bool own = false) {
    c.columns = cols(G, k, in, val);
    kinds[kind].hardware.push_back(add(c));
    if (!pooled) return kinds[kind].hardware.back();
    const std::size_t hw = kinds[kind].hardware.back();
    for (int r = 0; r < R; ++r) {
      if (!any(G, [in, r](const ObsGeom& g) { return g.rec == r && in(g); })) continue;  // none of its observations
      Candidate cr = c;
      cr.scope.recording = recs[static_cast<std::size_t>(r)].name;
      cr.scope_only = !own;
      cr.columns = cols(G, k, [in, r](const ObsGeom& g) { return g.rec == r && in(g); }, val);
      kinds[kind].per_recording.push_back(add(cr));
      p.catalogue[hw].replicates.push_back(kinds[kind].per_recording.back());
    }
    return hw;
  }

  std::string rec_name(int r) const { return recs[static_cast<std::size_t>(r)].name; }

  // The targets with observations selected by `in` (one recording alone), if there are at least
  // kMinCommonTargets of them: a picture of many targets, where a sensor's common offset is asked
  // across its targets (below); else none (the Autoferry recordings' two or three boats).
  std::vector<std::string> many_targets(const std::function<bool(const ObsGeom&)>& in) const {
    if (pooled) return {};
    std::vector<std::string> out;
    for (const auto& t : targets)
      if (any(G, [&](const ObsGeom& g) { return g.target == t && in(g); })) out.push_back(t);
    return static_cast<int>(out.size()) >= kMinCommonTargets ? out : std::vector<std::string>{};
  }

  // Sensor entry hw asked across the targets: one scope_only copy per target (its replicates,
  // replication.hpp), so it enters only when the targets' values agree on it (their
  // random-effects mean significant; with one_value, also one value by Cochran's Q).
  void across_targets(std::size_t hw, const std::vector<std::string>& ts, const std::function<bool(const ObsGeom&)>& in,
                      const Val& val, int k, bool one_value) {
    for (const auto& t : ts) {
      Candidate cr = p.catalogue[hw];
      cr.scope.target = t;
      cr.scope_only = true;
      cr.replicates.clear();
      cr.columns = cols(G, k, [in, t](const ObsGeom& g) { return g.target == t && in(g); }, val);
      const std::size_t i = add(cr);
      p.catalogue[hw].replicates.push_back(i);
    }
    p.catalogue[hw].one_value = one_value;
  }

  // Per sensor: its clock, its bearing bias, and a bearing step in each recording.
  void add_sensor_entries() {
    const std::string rate_sig = "the rate of the sensor's measurement (target and observer motion)";
    for (const auto& s : sensors) {
      auto is_s = [s](const ObsGeom& g) { return g.sensor == s; };
      auto is_sb = [s](const ObsGeom& g) { return g.sensor == s && !g.is_range; };
      sensor_clock.push_back(hardware("sensor clocks (time_offset)", {"time_offset", {s, ""}, {"s"}, rate_sig, "", {}, {}}, 1, is_s, rate_column));
      // many targets: the clock is their random-effects mean (an echo ahead of or behind its
      // antenna along the hull moves a ship's measurements as a clock would, either way)
      const auto ts_c = many_targets(is_s);
      if (!ts_c.empty()) across_targets(sensor_clock.back(), ts_c, is_s, rate_column, 1, false);
      sensor_bias.push_back(hardware("sensor bearing biases (bearing_bias)",
                                     {"bearing_bias", {s, ""}, {"rad"}, "a constant on this sensor's bearings", "", {}, {}}, 1, is_sb,
                                     unit_column, true));
      // many targets: the bias is their random-effects mean (each hull's echo lies to port or to
      // starboard of its antenna as often as not: those departures average out)
      const auto ts_b = many_targets(is_sb);
      if (!ts_b.empty()) across_targets(sensor_bias.back(), ts_b, is_sb, unit_column, 1, false);
      for (int r = 0; r < R; ++r) {  // a step belongs to one recording
        if (!any(G, [s, r](const ObsGeom& g) { return g.rec == r && g.sensor == s && !g.is_range; })) continue;
        std::vector<double> grid;
        for (int k = 0; k < o.step_grid; ++k) grid.push_back(t0[r] + (t1[r] - t0[r]) * (0.1 + 0.8 * k / (o.step_grid - 1)));
        add({"bias_step", {s, "", pooled ? rec_name(r) : ""}, {"rad"}, "a jump in this sensor's bearings at one time", "t_s", grid,
             cols(G, 1, [s, r](const ObsGeom& g) { return g.rec == r && g.sensor == s && !g.is_range; },
                  [grid](const ObsGeom& g, std::size_t v) { return multi_effect::step(g, grid[v]); })});
      }
    }
  }

  // Per range sensor: its range bias and gain, and its scan stamps where it scans slowly enough.
  void add_range_sensor_entries() {
    for (const auto& s : range_sensors) {
      auto is_sr = [s](const ObsGeom& g) { return g.sensor == s && g.is_range; };
      const std::size_t rb = hardware("range biases (range_bias)",
                                      {"range_bias", {s, ""}, {"m"}, "a constant on this sensor's ranges", "", {}, {}}, 1, is_sr,
                                      unit_column, true);
      // many targets: one value for all of them (Cochran's Q), since every hull's echo comes from
      // its near side (a shortfall of up to its length, never a surplus): a mean of such offsets
      // is no radar bias. Each target's own offset is its entry (echo_range_offset), bounded by
      // its hull's length.
      const auto ts_r = many_targets(is_sr);
      if (!ts_r.empty()) {
        across_targets(rb, ts_r, is_sr, unit_column, 1, true);
        for (const auto& t : ts_r) {
          if (add_near_side_echo(s, t)) continue;  // a moving ship seen over many aspects
          Candidate e{"echo_range_offset", {s, t}, {"m"}, "a constant on " + s + "'s ranges of this target (where its echo lies on the hull)",
                      "", {}, cols(G, 1, [s, t](const ObsGeom& g) { return g.sensor == s && g.target == t && g.is_range; }, unit_column)};
          e.bound = hull_length_bound(t);
          add(e);
        }
      }
      const Val range_col = [](const ObsGeom& g, std::size_t) { return multi_effect::range_gain(g); };
      const std::size_t rg = hardware("range gains (range_gain)", {"range_gain", {s, ""}, {"1"}, "the range", "", {}, {}}, 1, is_sr, range_col);
      if (!ts_r.empty()) across_targets(rg, ts_r, is_sr, range_col, 1, true);  // the near sides, as the range bias
      const auto T = mp.scan_period_s.count(s) ? mp.scan_period_s.at(s) : NAN;
      if (std::isfinite(T) && T >= o.min_sweep_period_s) {
        // scan_time_offset: dt = c + f ((beta_end - beta) mod 2 pi) / omega (sweep_delay_s), beta_end scanned
        std::vector<double> grid;
        for (int k = 0; k < o.sweep_grid; ++k) grid.push_back(360.0 * k / o.sweep_grid);
        auto is_s = [s](const ObsGeom& g) { return g.sensor == s; };
        hardware("scan stamps (scan_time_offset)",
                 {"scan_time_offset", {s, ""}, {"c_s", "sweep_frac"},
                  "the rate of the sensor's measurement, and its bearing within the sweep (period " + period_text(T) + " s)",
                  "sweep_end_deg", grid, {}},
                 2, is_s, [grid, T](const ObsGeom& g, std::size_t v) { return multi_effect::scan_stamp(g, grid[v] * M_PI / 180, T); });
      }
    }
  }

  // A moving ship's near-side echo by its aspect. A hull of half-length a and half-beam b about
  // its centre, seen along the unit line of sight e (range Jacobian), shows its echo short of the
  // centre by the rectangle's support function (the nearest side; e.g. end-on a, broadside b):
  //   dr = -(a |e . u| + b |e . u_perp|),   u the ship's course, u_perp to starboard
  // (the centre's place off the antenna is antenna_offset's; far field: the nearest corner's
  // sideways distance p adds p^2 / 2r, 2.5 m for p = 100 m at 2 km). Only for a ship whose course
  // is known (moving faster than the association's min_speed_mps) at kMinCourseFraction of its
  // ranges (the others take the mean aspect), and seen over aspects spread by kMinAspectSpreadDeg
  // between their 10th and 90th percentiles (folded into [0, 90] deg): over a narrower spread
  // the two columns are one constant, and the ship's echo is that constant (echo_range_offset)
  // instead. A moored ship has no course in its reference (AIS gives none at rest), so its echo
  // is that constant too. True if the entry was added (then in place of the constant).
  static constexpr double kMinCourseFraction = 0.8;
  static constexpr double kMinAspectSpreadDeg = 20;
  static Eigen::RowVectorXd aspect_columns(const ObsGeom& g) { return multi_effect::near_side(g); }
  bool add_near_side_echo(const std::string& s, const std::string& t) {
    auto in = [s, t](const ObsGeom& g) { return g.sensor == s && g.target == t && g.is_range; };
    std::vector<double> chi;
    Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(2);
    std::size_t n = 0;
    for (const ObsGeom& g : *G) {
      if (!in(g)) continue;
      ++n;
      if (g.u.squaredNorm() == 0) continue;
      const Eigen::RowVectorXd c = aspect_columns(g);
      mean += c;
      chi.push_back(std::atan2(-c[1], -c[0]) * 180 / M_PI);  // folded aspect [deg], 0 end-on
    }
    if (chi.empty() || static_cast<double>(chi.size()) < kMinCourseFraction * static_cast<double>(n)) return false;
    std::sort(chi.begin(), chi.end());
    const auto pct = [&chi](double q) { return chi[static_cast<std::size_t>(q * static_cast<double>(chi.size() - 1))]; };
    if (pct(0.9) - pct(0.1) < kMinAspectSpreadDeg) return false;
    mean /= static_cast<double>(chi.size());
    Candidate e{"near_side_echo", {s, t}, {"half_length_m", "half_beam_m"},
                "the ship's aspect on " + s + "'s ranges of this target (its hull's nearest side)", "", {},
                cols(G, 2, in, [mean](const ObsGeom& g, std::size_t) -> Eigen::RowVectorXd {
                  return g.u.squaredNorm() > 0 ? aspect_columns(g) : mean;
                })};
    e.bound = near_side_bound(t);
    add(e);
    return true;
  }

  // A near-side echo's physical bound: its half-extents lie on the hull, 0 <= a <= L and
  // 0 <= b <= B (kHullBoundSe above; below 0 by more than 2 SE: an echo from beyond the centre,
  // away from the radar, is no near side).
  std::function<std::string(const std::vector<double>&, const std::vector<double>&)> near_side_bound(const std::string& t) const {
    const auto it = o.hull.find(t);
    const bool known = it != o.hull.end() && std::isfinite(it->second.length_m) && std::isfinite(it->second.beam_m);
    const double L = known ? it->second.length_m : o.max_hull_length_m, B = known ? it->second.beam_m : o.max_hull_beam_m;
    return [t, L, B, known](const std::vector<double>& x, const std::vector<double>& se) -> std::string {
      const bool beyond = x[0] - kHullBoundSe * se[0] > L || x[1] - kHullBoundSe * se[1] > B;
      const bool behind = x[0] + 2 * se[0] < 0 || x[1] + 2 * se[1] < 0;
      if (!beyond && !behind) return "";
      return printf_string(
          "a near-side echo of half-length %.3g m, half-beam %.3g m (+- %.2g, %.2g) %s target %s (%s %.3g m long, %.3g m "
          "wide%s): a sign that detections of something else were associated to it%s",
          x[0], x[1], se[0], se[1], beyond ? "is beyond the hull of" : "lies behind the centre of", t.c_str(),
          known ? "on record" : "at most", L, B, known ? ", targets.csv" : ", its size not on record",
          known ? ", or that its size on record is wrong" : "");
    };
  }

  // An antenna or hull offset's physical bound: the sensed point and the reference's antenna
  // both lie on the hull, so |along| <= its length and |starboard| <= its beam (kHullBoundSe;
  // MultiProblemOptions::hull, or the largest ship afloat for a target of
  // unknown size). Beyond it the offset is not the hull's: detections of something else were
  // associated to the target (or its size on record is wrong).
  std::function<std::string(const std::vector<double>&, const std::vector<double>&)> hull_bound(const std::string& t) const {
    const auto it = o.hull.find(t);
    const bool known_l = it != o.hull.end() && std::isfinite(it->second.length_m);
    const bool known_b = it != o.hull.end() && std::isfinite(it->second.beam_m);
    const double L = known_l ? it->second.length_m : o.max_hull_length_m, B = known_b ? it->second.beam_m : o.max_hull_beam_m;
    return [t, L, B, known_l, known_b](const std::vector<double>& x, const std::vector<double>& se) -> std::string {
      const bool along = std::abs(x[0]) - kHullBoundSe * se[0] > L, starboard = std::abs(x[1]) - kHullBoundSe * se[1] > B;
      if (!along && !starboard) return "";
      return printf_string(
          "an offset of %.3g m along, %.3g m starboard (+- %.2g, %.2g) is beyond the hull of target %s (%s %.3g m long, %.3g m "
          "wide%s): not where its antenna or hull is, but a sign that detections of something else were associated "
          "to it%s",
          x[0], x[1], se[0], se[1], t.c_str(), known_l || known_b ? "on record" : "at most", L, B,
          known_l || known_b ? ", targets.csv" : ", the largest ships afloat; its size is not on record",
          known_l || known_b ? ", or that its size on record is wrong" : "");
    };
  }

  // An echo's range offset from the target's antenna: at most its hull's length (kHullBoundSe).
  std::function<std::string(const std::vector<double>&, const std::vector<double>&)> hull_length_bound(const std::string& t) const {
    const auto it = o.hull.find(t);
    const bool known = it != o.hull.end() && std::isfinite(it->second.length_m);
    const double L = known ? it->second.length_m : o.max_hull_length_m;
    return [t, L, known](const std::vector<double>& x, const std::vector<double>& se) -> std::string {
      if (!(std::abs(x[0]) - kHullBoundSe * se[0] > L)) return "";
      return printf_string(
          "a range offset of %.3g m (+- %.2g) is beyond the hull of target %s (%s %.3g m long%s): a sign that detections "
          "of something else were associated to it%s",
          x[0], se[0], t.c_str(), known ? "on record" : "at most", L, known ? ", targets.csv" : ", its size not on record",
          known ? ", or that its size on record is wrong" : "");
    };
  }

  // A reference's clock offset: at most max_reference_clock_s (kHullBoundSe).
  std::function<std::string(const std::vector<double>&, const std::vector<double>&)> reference_clock_bound(const std::string& t) const {
    const double lim = o.max_reference_clock_s;
    return [t, lim](const std::vector<double>& x, const std::vector<double>& se) -> std::string {
      if (!(std::abs(x[0]) - kHullBoundSe * se[0] > lim)) return "";
      return printf_string(
          "a reference clock offset of %.3g s (+- %.2g) for target %s is beyond %.3g s (a GNSS or AIS position is "
          "stamped with its fix's time): it stands in for something else, e.g. an echo along the hull away from its antenna",
          x[0], se[0], t.c_str(), lim);
    };
  }

  // Per target: its reference clock in each recording (and, pooled, per boat), its antenna
  // offset, and its hull offset as each range sensor sees it.
  void add_target_entries() {
    auto offset_cols = [](const ObsGeom& g, std::size_t) { return multi_effect::hull_offset(g); };
    auto truth_rate = [](const ObsGeom& g, std::size_t) { return multi_effect::reference_clock(g); };
    const std::string off_sig = "the line-of-sight component of the target's heading (aspect)";
    const std::string truth_sig = "the rate due to the target's own motion (the same for every sensor)";
    for (const auto& t : targets) {
      auto is_t = [t](const ObsGeom& g) { return g.target == t; };
      for (int r = 0; r < R; ++r)  // a reference clock belongs to one recording
        if (any(G, [t, r](const ObsGeom& g) { return g.rec == r && g.target == t; })) {
          Candidate c{"truth_time_offset", {"", t, pooled ? rec_name(r) : ""}, {"s"}, truth_sig, "", {},
                      cols(G, 1, [t, r](const ObsGeom& g) { return g.rec == r && g.target == t; }, truth_rate)};
          c.bound = reference_clock_bound(t);
          target_clock.push_back(add(c));
        }
      if (pooled)  // "the same in seconds in every recording": the boat's reference logger
        target_clock_hw.push_back(hardware("reference clocks (truth_time_offset per boat)",
                                           {"truth_time_offset", {"", t}, {"s"}, truth_sig, "", {}, {}}, 1, is_t, truth_rate));
      Candidate boat{"antenna_offset", {"", t}, {"along_m", "starboard_m"}, off_sig, "", {}, {}};
      boat.bound = hull_bound(t);
      target_offset.push_back(hardware("boat antenna offsets (antenna_offset per target)", boat, 2, is_t, offset_cols));
      for (const auto& s : range_sensors) {
        Candidate pair{"antenna_offset", {s, t}, {"along_m", "starboard_m"}, off_sig + " seen by " + s, "", {}, {}};
        pair.bound = hull_bound(t);
        pair_offset.push_back(hardware("hull offsets per sensor and target (antenna_offset)", pair, 2,
                                       [s, t](const ObsGeom& g) { return g.sensor == s && g.target == t; }, offset_cols));
      }
    }
  }

  // With several sensors: the observer's one clock and its heading, common to every sensor.
  void add_common_entries() {
    if (sensors.size() <= 1) return;
    common_clock = hardware("the observer's clock (common time_offset)",
                            {"time_offset", {"", ""}, {"s"}, "the rate of every sensor's measurement (one clock)", "", {}, {}}, 1,
                            [](const ObsGeom&) { return true; }, rate_column);
    common_bias = hardware("the observer's heading (common bearing_bias)",
                           {"bearing_bias", {"", ""}, {"rad"}, "a constant on every sensor's bearings (the observer's heading)", "", {}, {}},
                           1, [](const ObsGeom& g) { return !g.is_range; }, unit_column);
  }

  // The scope questions between the entries added: which clock, which bias, which offset, and,
  // pooled, each hardware kind against its per-recording values.
  void add_scope_questions() {
    ScopeQuestion clock{"which clock is off: the sensors', the targets' references', both, or one common clock?", {}};
    clock.alternatives.push_back({"per sensor", sensor_clock});
    clock.alternatives.push_back({pooled ? "per target reference and recording" : "per target reference", target_clock});
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
    if (pooled) {
      for (const auto& [kind, k] : kinds)
        p.scope_questions.push_back({kind + ": one value in every recording (hardware), or one per recording?",
                                     {{"one value in every recording", k.hardware}, {"one per recording", k.per_recording}}});
      p.scope_questions.push_back({"a boat's offset along its track: the same in metres (antenna offset), the same in seconds "
                                   "(reference clock), or per recording?",
                                   {{"the same in metres (antenna_offset per boat)", target_offset},
                                    {"the same in seconds (truth_time_offset per boat)", target_clock_hw},
                                    {"per recording (truth_time_offset per boat and recording)", target_clock}}});
    }
  }

  MultiProblem& mp;
  Problem& p;
  const std::vector<RecordingDetections>& recs;
  const MultiProblemOptions& o;
  const std::vector<double>& t0;
  const std::vector<double>& t1;
  const Geoms G;
  const bool pooled;
  const int R;
  std::set<std::string> sensors, targets, range_sensors;
  std::map<std::string, Kind> kinds;  // scope-question key -> entries
  std::vector<std::size_t> sensor_clock, target_clock, sensor_bias, pair_offset, target_offset, target_clock_hw;
  std::size_t common_clock = 0, common_bias = 0;
};

// The covariates of each observation for what stays unexplained: range, target speed, time
// since its recording's start, aspect.
void add_covariates(Problem& p, const std::vector<ObsGeom>& geoms, const std::vector<double>& t0) {
  const auto n = static_cast<std::size_t>(p.y.size());
  std::vector<double> range(n), aspect(n), speed(n), time(n);
  for (std::size_t i = 0; i < geoms.size(); ++i) {
    const auto& g = geoms[i];
    range[i] = g.range_pred;
    speed[i] = g.v_target.norm();
    time[i] = g.t - t0[static_cast<std::size_t>(g.rec)];
    aspect[i] = g.dh * g.u_perp;  // the line-of-sight cross-component of the hull axis
  }
  p.covariates = {{"range", range}, {"target speed", speed}, {"time", time}, {"aspect (hull across the line of sight)", aspect}};
}

}  // namespace

MultiProblem build_multi_problem(const std::vector<RecordingDetections>& recs, const MultiProblemOptions& o) {
  check_inputs(recs, o);
  const int R = static_cast<int>(recs.size());
  MultiProblem mp;
  Problem& p = mp.problem;
  std::vector<double> t0(R), t1(R);
  set_spans(recs, o, mp, t0, t1);

  // channels in a fixed order: recording, sensor, target, quantity
  ObsTables obs;
  for (int r = 0; r < R; ++r) add_recording(recs, r, o, mp, obs);
  if (p.channels.empty()) throw ConfigError("multi diagnosis: no sensor:target pair with " + std::to_string(kMinPairDetections) +
                                             " or more associated detections");
  add_interpolation_noise(p, obs.interp_sd, obs.interval);
  const auto n = static_cast<Eigen::Index>(p.y.size());
  p.nuisance = Eigen::MatrixXd(n, 0);
  const Geoms G = std::make_shared<const std::vector<ObsGeom>>(std::move(obs.geoms));

  CatalogueBuilder catalogue(mp, recs, o, t0, t1, G);
  catalogue.add_sensor_entries();
  catalogue.add_range_sensor_entries();
  catalogue.add_target_entries();
  catalogue.add_common_entries();
  // scope questions
  catalogue.add_scope_questions();

  // covariates for what stays unexplained
  add_covariates(p, *G, t0);
  return mp;
}

}  // namespace rnav
