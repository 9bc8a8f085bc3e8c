#include "estimators/diagnosis/io/lcm_log_input.hpp"

#include "common/node/channels.hpp"
#include "common/io/config.hpp"
#include "estimators/diagnosis/io/lcm_log_streams.hpp"
#include "common/node/site_context.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/bearing_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>
#include <rnav/target_truth_batch_t.hpp>

namespace rnav {

namespace {

// What a UAV log's reader needs of its scenario: the runner (its epoch).
struct SiteRunner {
  RunnerOptions runner;
};

// A batch holds the samples whose time falls in its window [utime_begin, utime_end): a sample
// outside it has a corrupt time stamp (e.g. one flipped bit), which must not be dropped silently.
struct WindowCheck {
  std::string file, realization;
  void operator()(const batch_header_t& h, std::int64_t utime, const char* channel) const {
    if (utime < h.utime_begin || utime >= h.utime_end)
      throw ConfigError(file + ": " + channel + realization + ", window " + std::to_string(h.window) + " (seq " +
                        std::to_string(h.seq) + "): a sample at utime " + std::to_string(utime) +
                        " us outside the batch's window [" + std::to_string(h.utime_begin) + ", " +
                        std::to_string(h.utime_end) + ") us (a corrupt time stamp)");
  }
};

/// [us] A nav solution reaches the ground after its time of validity, within the data link's
/// latency (the scenario's snsins.latency_s is in [0, 10] s).
constexpr double kMaxNavAgeUs = 10e6;

/// The solution's time of validity against its arrival (which WindowCheck bounds).
void check_nav_age(const std::string& file, const std::string& realization, const batch_header_t& h,
                   const nav_solution_t& n) {
  // In double: corrupt values must not overflow the difference.
  const double age_us = static_cast<double>(n.link_utime) - static_cast<double>(n.utime);
  if (!(age_us >= 0 && age_us <= kMaxNavAgeUs))
    throw ConfigError(file + ": " + ch::kNav + realization + ", window " + std::to_string(h.window) + " (seq " +
                      std::to_string(h.seq) + "): a solution's time of validity utime " + std::to_string(n.utime) +
                      " us is not within 10 s before its arrival link_utime " + std::to_string(n.link_utime) +
                      " us (a corrupt time stamp)");
}

// The scenario document of the run: --scenario FILE if given, else the log's SIM_SCENARIO;
// --set overrides on top; `read` takes the shared sections the reader needs (ConfigErrors
// prefixed with where the document came from). Its sim time 0 must be the log's (else it is
// another run's scenario).
template <class Read>
auto scenario_of(const LcmLogStreams& log, const LcmLogOptions& o, const std::string& kind, Read&& read) {
  std::string what;
  nlohmann::json doc;
  if (!o.scenario_file.empty()) {
    const std::string k = scenario_kind(o.scenario_file);
    if (k != kind)
      throw ConfigError("--scenario " + o.scenario_file + " is a '" + k + "' scenario, but diagnose " +
                        kind + " needs a '" + kind + "' one");
    what = o.scenario_file;
    doc = load_json_file(o.scenario_file);
    for (const auto& ov : o.overrides) apply_override(doc, ov);
  } else {
    const sim_scenario_t* s = log.scenario();
    if (!s)
      throw ConfigError(log.file() + ": the log has no SIM_SCENARIO message for realization " +
                        std::to_string(log.realization()) +
                        " (recorded before runs published it, or filtered out), so the site is "
                        "unknown: pass the run's --scenario FILE and its --set options");
    if (s->kind != kind)
      throw ConfigError(log.file() + ": the log holds a '" + s->kind + "' run (SIM_SCENARIO); use diagnose " +
                        s->kind);
    what = log.file() + ": SIM_SCENARIO (scenario " + s->source + ")";
    doc = parse_json_checked(s->scenario_json, what + ": not valid JSON", /*allow_comments=*/false);
  }
  decltype(read(doc)) sc;
  try {
    if (o.scenario_file.empty())
      for (const auto& ov : o.overrides) apply_override(doc, ov);
    sc = read(doc);
  } catch (const ConfigError& e) {
    throw ConfigError(what + ": " + e.what());
  }
  if (sc.runner.epoch_utime != log.start_utime())
    throw ConfigError(log.file() + ": realization " + std::to_string(log.realization()) +
                      " starts at utime " + std::to_string(log.start_utime()) +
                      " but the scenario's runner.epoch_utime is " + std::to_string(sc.runner.epoch_utime) +
                      ": not the scenario of this run");
  return sc;
}

std::string scenario_note(const LcmLogOptions& o) {
  return o.scenario_file.empty() ? "; scenario from the log's SIM_SCENARIO"
                                 : "; scenario from " + o.scenario_file;
}

}  // namespace

PrlFlightData read_prl_lcm_log(const std::string& file, const LcmLogOptions& o, std::string* summary) {
  LcmLogStreams log;
  log.add_stream<aircraft_truth_batch_t>(ch::kTruth);
  log.add_stream<prl_plot_batch_t>(ch::kApoi);
  log.add_stream<nav_batch_t>(ch::kNav);
  log.read(file, o.realization, "prl");
  const SiteContext sc = scenario_of(log, o, "prl", read_site_context);

  PrlFlightData d;
  d.radar_site = sc.radar_site();
  d.azimuth_reference_deg = sc.radar.azimuth_reference_deg;
  d.threshold = sc.runway.threshold;
  d.heading_deg = sc.runway.heading_deg;
  auto t_of = [&](std::int64_t u) { return (u - sc.runner.epoch_utime) * 1e-6; };
  const std::string r = ", realization " + std::to_string(o.realization);
  const WindowCheck in_window{file, r};
  for (const auto* b : log.batches<aircraft_truth_batch_t>(ch::kTruth))
    for (const auto& s : b->states) {
      in_window(b->header, s.utime, ch::kTruth);
      d.truth.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
    }
  for (const auto* b : log.batches<prl_plot_batch_t>(ch::kApoi))
    for (const auto& p : b->plots) {
      in_window(b->header, p.utime, ch::kApoi);
      d.t_s.push_back(t_of(p.utime));
      d.plots.push_back({p.range_m, p.course_rad, p.glide_rad});
    }
  for (const auto* b : log.batches<nav_batch_t>(ch::kNav))
    for (const auto& n : b->solutions) {
      in_window(b->header, n.link_utime, ch::kNav);  // a nav batch holds the solutions received in its window
      check_nav_age(file, r, b->header, n);
      d.nav.push_back({t_of(n.utime), {n.lat_deg, n.lon_deg, n.h_m}});
    }
  if (d.plots.size() < 10) throw ConfigError(file + ": " + ch::kApoi + r + ": fewer than 10 plots");
  if (d.nav.size() < 2) throw ConfigError(file + ": " + ch::kNav + r + ": fewer than 2 solutions");
  d.validate(file + r);
  if (summary) *summary = log.summary() + scenario_note(o);
  return d;
}

AzimuthData read_uav_lcm_log(const std::string& file, const LcmLogOptions& o, std::string* summary) {
  LcmLogStreams log;
  log.add_stream<observer_batch_t>(ch::kUavNav);
  log.add_stream<bearing_batch_t>(ch::kUavBearing);
  log.add_stream<target_truth_batch_t>(ch::kTruthTarget);
  log.read(file, o.realization, "uav");
  const auto sc = scenario_of(log, o, "uav", [](const nlohmann::json& doc) { return SiteRunner{read_runner_options(doc)}; });

  AzimuthData d;
  auto t_of = [&](std::int64_t u) { return (u - sc.runner.epoch_utime) * 1e-6; };
  const std::string r = ", realization " + std::to_string(o.realization);
  const WindowCheck in_window{file, r};
  for (const auto* b : log.batches<observer_batch_t>(ch::kUavNav))
    for (const auto& s : b->states) {
      in_window(b->header, s.utime, ch::kUavNav);
      d.observer.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
    }
  std::int64_t last = 0;
  for (const auto* b : log.batches<bearing_batch_t>(ch::kUavBearing))
    for (const auto& x : b->bearings) {
      in_window(b->header, x.utime, ch::kUavBearing);
      if (d.frames.empty() || x.utime != last) d.frames.push_back({t_of(x.utime), {}});
      last = x.utime;
      d.frames.back().bearings_rad.push_back(x.bearing_rad);
    }
  for (const auto* b : log.batches<target_truth_batch_t>(ch::kTruthTarget))
    for (const auto& s : b->states) {
      in_window(b->header, s.utime, ch::kTruthTarget);
      d.truth.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, 0.0}});
    }
  if (d.observer.size() < 2) throw ConfigError(file + ": " + ch::kUavNav + r + ": fewer than 2 states");
  if (d.frames.size() < 10) throw ConfigError(file + ": " + ch::kUavBearing + r + ": fewer than 10 frames");
  d.validate(file + r);
  if (summary) *summary = log.summary() + scenario_note(o);
  return d;
}

}  // namespace rnav
