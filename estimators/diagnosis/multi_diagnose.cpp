#include "estimators/diagnosis/multi_diagnose.hpp"

#include "common/io/atomic_file.hpp"

#include "common/io/config.hpp"
#include "common/io/did_you_mean.hpp"
#include "estimators/diagnosis/diagnose_report.hpp"
#include "estimators/diagnosis/multi_problem.hpp"
#include "estimators/model_id/parallel_for.hpp"
#include "estimators/model_id/progress_clock.hpp"
#include "estimators/model_id/search_json.hpp"
#include "estimators/model_id/stats.hpp"
#include "estimators/diagnosis/target_model.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <set>
#include <stdexcept>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>

namespace rnav {

namespace {

MultiProblemOptions problem_options(const MultiDiagnoseOptions& o) {
  MultiProblemOptions po;
  po.sigma_bearing_rad = o.sigma_bearing_deg * kDegToRad;
  po.sigma_range_m = o.sigma_range_m;
  po.split_fraction = o.split_fraction;
  po.step_grid = o.step_grid;
  po.max_hull_length_m = o.max_hull_length_m;
  po.max_hull_beam_m = o.max_hull_beam_m;
  return po;
}

// The hardware effects of `fit` (entries without a recording), each at the mean over the
// recordings it was fitted on (random effects) where it has one, else at its pooled estimate.
std::vector<AppliedEffect> hardware_of(const SearchResult& fit) {
  std::vector<AppliedEffect> out;
  for (const FoundEffect& e : fit.effects) {
    if (!e.scope.recording.empty()) continue;  // one recording's own: not carried over
    out.push_back({e.name, e.scope.sensor, e.scope.target, e.replication.tested ? e.replication.mean : e.estimate,
                   e.scan_param.empty() ? NAN : e.scan_value});
  }
  return out;
}

// The effects of `fit` that belong to recording `name` alone, as AppliedEffect (the recording
// dropped from their scope: as they are in that recording's own problem).
std::vector<AppliedEffect> own_of(const SearchResult& fit, const std::string& name) {
  std::vector<AppliedEffect> out;
  for (const FoundEffect& e : fit.effects)
    if (e.scope.recording == name)
      out.push_back({e.name, e.scope.sensor, e.scope.target, e.estimate, e.scan_param.empty() ? NAN : e.scan_value});
  return out;
}

// Per sensor: the median interval between its successive scans (distinct stamps, empty scans
// included) over every recording given [s] (the problem uses it for range sensors).
std::map<std::string, double> scan_periods(const std::vector<const MultiSensorData*>& recordings) {
  std::map<std::string, std::vector<double>> gaps;
  for (const MultiSensorData* rec : recordings) {
    std::map<std::string, double> last;
    for (const Detection& x : rec->detections) {
      const auto it = last.try_emplace(x.sensor, NAN).first;
      if (std::isfinite(it->second) && x.t_s > it->second) gaps[x.sensor].push_back(x.t_s - it->second);
      it->second = x.t_s;
    }
  }
  std::map<std::string, double> out;
  for (auto& [s, g] : gaps) {
    if (g.empty()) continue;
    std::nth_element(g.begin(), g.begin() + static_cast<std::ptrdiff_t>(g.size() / 2), g.end());
    out[s] = g[g.size() / 2];
  }
  return out;
}

// The targets whose reference jumped ("<recording>/<target>" or "<target>"): one text line each.
std::string reference_jumps_text(const std::map<std::string, ReferenceIntegrity>& jumps) {
  std::ostringstream o;
  for (const auto& [key, ri] : jumps) {
    if (!ri.uncovered.empty()) {
      o << "  reference " << key << ": does not cover";
      double span = 0;
      for (const auto& [a, b] : ri.uncovered) {
        o << " " << short_num(a - ri.detections_from_s) << "-" << short_num(b - ri.detections_from_s) << " s";
        span += b - a;
      }
      o << " of the detections' " << short_num(ri.detections_to_s - ri.detections_from_s) << " s (times from the first detection): "
        << ri.scans_left_out << " scans with " << ri.detections_left_out << " detections there left out for every target ("
        << short_num(span) << " s; the target's echoes there would be taken for another target's or for clutter)\n";
    }
    if (ri.jumps.empty()) continue;
    o << "  reference " << key << ": jumps";
    for (const auto& x : ri.jumps)
      o << " " << short_num(x.deviation_m) << " m off its path at t = " << short_num(x.t_s) << " s (" << short_num(x.t_s - ri.first_s)
        << " s after its first sample; a target bends off by at most " << short_num(x.bound_m) << " m there)";
    o << ": used only from " << short_num(ri.used_from_s - ri.first_s) << " to " << short_num(ri.used_to_s - ri.first_s)
      << " s after its first sample (" << ri.samples_used << " of " << ri.samples << " samples, the longest stretch without a jump)\n";
  }
  return o.str();
}

// The same as JSON: one object per jump (recording "" for one recording alone; recording names
// hold no '/').
nlohmann::ordered_json reference_jumps_json(const std::map<std::string, ReferenceIntegrity>& jumps) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const auto& [key, ri] : jumps) {
    const std::size_t slash = key.find('/');
    const std::string recording = slash == std::string::npos ? "" : key.substr(0, slash);
    const std::string target = slash == std::string::npos ? key : key.substr(slash + 1);
    for (const auto& x : ri.jumps)
      j.push_back({{"recording", recording}, {"target", target}, {"t_s", x.t_s}, {"deviation_m", x.deviation_m}, {"bound_m", x.bound_m},
                   {"used_from_s", ri.used_from_s}, {"used_to_s", ri.used_to_s}, {"samples", ri.samples},
                   {"samples_used", ri.samples_used}});
  }
  return j;
}

// The references' uncovered stretches as JSON: one object per target with any (recording "" for
// one recording alone).
nlohmann::ordered_json reference_coverage_json(const std::map<std::string, ReferenceIntegrity>& refs) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const auto& [key, ri] : refs) {
    if (ri.uncovered.empty()) continue;
    const std::size_t slash = key.find('/');
    nlohmann::ordered_json u = nlohmann::ordered_json::array();
    for (const auto& [a, b] : ri.uncovered) u.push_back({a, b});
    j.push_back({{"recording", slash == std::string::npos ? "" : key.substr(0, slash)},
                 {"target", slash == std::string::npos ? key : key.substr(slash + 1)}, {"uncovered_s", u},
                 {"scans_left_out", ri.scans_left_out}, {"detections_left_out", ri.detections_left_out}});
  }
  return j;
}

}  // namespace

MultiReport diagnose_multi(const MultiSensorData& data, const MultiDiagnoseOptions& o) {
  return diagnose_multi_pooled({{"", data}}, o);
}

MultiReport diagnose_multi_pooled(const std::vector<std::pair<std::string, MultiSensorData>>& recordings,
                                  const MultiDiagnoseOptions& o) {
  if (!(o.sigma_bearing_deg > 0) || !(o.sigma_range_m > 0)) throw ConfigError("multi diagnosis: nominal sigmas must be > 0");
  if (recordings.empty()) throw ConfigError("multi diagnosis: no recording");
  check_carry_options(o.carry);
  if (!(o.carry_alpha > 0 && o.carry_alpha < 0.5))
    throw ConfigError("multi diagnosis: carry alpha must be in (0, 0.5), got " + short_num(o.carry_alpha));
  const bool pooled = recordings.size() > 1;
  MultiReport rep;
  std::vector<RecordingDetections> recs;
  std::vector<std::map<std::string, ReferenceIntegrity>> jumped;  // per recording: the targets whose reference jumped
  for (const auto& [name, data] : recordings) {
    if (pooled && (name.empty() || name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") !=
                                       std::string::npos))
      throw ConfigError("multi diagnosis: recording name '" + name + "' must be [A-Za-z0-9_.-]+");
    std::map<std::string, SensorAssociation> st;
    std::map<std::string, ReferenceIntegrity> jumps;
    recs.push_back({pooled ? name : "", associate(data, o.association, st, &jumps)});
    for (auto& [s, x] : st) rep.association[pooled ? name + "/" + s : s] = x;
    for (auto& [t, x] : jumps) rep.reference_jumps[pooled ? name + "/" + t : t] = x;
    jumped.push_back(std::move(jumps));
    if (pooled) rep.recordings.push_back(name);
  }
  MultiProblemOptions po = problem_options(o);
  std::vector<const MultiSensorData*> all;
  for (const auto& rec : recordings) all.push_back(&rec.second);
  po.scan_period_s = scan_periods(all);
  for (const auto& rec : recordings)  // each boat's size on record (the first recording that gives one)
    for (const auto& [t, h] : rec.second.hull) po.hull.emplace(t, h);
  MultiProblem mp = build_multi_problem(recs, po);
  rep.split_time_s = mp.split_time_s.front();
  rep.split_fraction = o.split_fraction;
  rep.dropped_channels = mp.dropped_channels;
  rep.scan_period_s = mp.scan_period_s;
  check_limit_entries(mp.problem, o.search.injection, "diagnose multi");
  // the searches of these recordings below (the report's, the carried fit's, the leave-one-out's)
  // share one memo of noise fits: the channels of a recording are the same in each
  SearchOptions search = o.search;
  if (!search.noise_memo) search.noise_memo = make_noise_memo();
  rep.result = search_effects(mp.problem, search);
  const SearchResult& r = rep.result;

  // gain per sensor:target (per recording): compensated measurement against the held-out reference
  PairErrors pe;
  for (std::size_t k = 0; k < recs.size(); ++k) {
    const auto& a = recs[k].a;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i].t_s < mp.split_time_s[k]) continue;
      const long ib = mp.bearing_obs[k][i], ir = mp.range_obs[k][i];
      if (ib < 0) continue;
      const auto yb = mp.problem.y[static_cast<std::size_t>(ib)];
      const bool range = a[i].has_range && ir >= 0;
      const double yr = range ? mp.problem.y[static_cast<std::size_t>(ir)] : 0.0;
      pe.add((pooled ? recs[k].name + "/" : "") + a[i].sensor + ":" + a[i].target, a[i], yb - r.nominal_oos(ib),
             yb - r.extended_oos(ib), range, range ? yr - r.nominal_oos(ir) : 0.0, range ? yr - r.extended_oos(ir) : 0.0);
    }
  }
  for (const LeaveOneOutRow& x : pe.rows(""))
    rep.gain[x.pair] = {x.n, x.nominal_rms, x.extended_rms, x.unit};

  if (o.test_target_model) {
    TargetModelOptions to;
    to.search = o.search;
    to.threads = o.search.injection.threads;
    for (std::size_t k = 0; k < recordings.size(); ++k) {
      const auto& [name, data] = recordings[k];
      auto tracks = data.truth_on_level();  // as associated: a reference that jumped, on its stretch without jumps
      for (const auto& [target, ri] : jumped[k]) tracks[target] = used_stretch(tracks[target], ri);
      const TargetModelResult tm = test_target_model(tracks, LocalLevelFrame(data.observer.front().g, 0.0), to);
      for (FoundEffect e : tm.maneuvers) {
        e.scope.recording = pooled ? name : "";
        rep.target_effects.push_back(e);
      }
      for (const auto& n : tm.notes) rep.target_notes.push_back(pooled ? name + ": " + n : n);
    }
  }

  // each recording's problem built once (scan periods of all of them, as every fit uses), to
  // score carried hardware on: the recordings a fit saw (its shares) and the one it did not
  std::vector<AppliedScorer> scorers;
  for (const RecordingDetections& rec : recs) scorers.emplace_back(rec, mp.scan_period_s, po);
  // pooled, the carried hardware comes from a fit at carry_alpha (no injected limits): the
  // report's own fit where the levels are the same
  SearchOptions carry_search = search;
  carry_search.injection.injections = 0;
  if (pooled) carry_search.alpha = o.carry_alpha;
  {
    SearchResult carry_fit;
    const bool own_fit = carry_search.alpha == o.search.alpha;
    if (!own_fit) {
      if (o.search.progress) o.search.progress("the fit carried to new recordings, at alpha " + short_num(carry_search.alpha));
      SearchOptions so = carry_search;
      so.progress = nullptr;
      carry_fit = search_effects(mp.problem, so);
    }
    const SearchResult& cf = own_fit ? r : carry_fit;
    std::vector<FittedRecording> every;
    for (std::size_t k = 0; k < recs.size(); ++k)
      every.push_back({&scorers[k], pooled ? own_of(cf, recs[k].name) : std::vector<AppliedEffect>{}});
    rep.carry = carry_no_harm(hardware_of(cf), every, o.carry);
    rep.carry_alpha = carry_search.alpha;
  }

  // leave one recording out: fit on the others (no injected limits), carry its hardware as the
  // rule above chooses on those others, score the one left out
  if (pooled && o.leave_one_out) {
    SearchOptions so = carry_search;
    so.threads = 1;  // the recordings left out are searched at once instead
    so.progress = nullptr;  // one line per recording left out instead (below)
    const std::size_t R = recs.size();
    std::vector<std::vector<LeaveOneOutRow>> rows(R);
    std::vector<std::vector<std::string>> carried(R);
    std::vector<CarriedHardware> shares(R);
    // a line per recording done, with the time left at the mean time per recording so far (the
    // lines go to the caller; no result depends on them)
    const ProgressClock clock(R);
    std::mutex done_m;
    std::size_t done = 0;
    parallel_for(R, o.search.injection.threads, [&](std::size_t k) {
      try {
        std::vector<RecordingDetections> rest;
        for (std::size_t j = 0; j < R; ++j)
          if (j != k) rest.push_back(recs[j]);
        if (o.search.progress)
          o.search.progress("leave one out: the others without recording " + std::to_string(k + 1) + " of " + std::to_string(R));
        const MultiProblem fp = build_multi_problem(rest, po);
        const SearchResult fr = search_effects(fp.problem, so);
        // two or more recordings fitted (R >= 3): their own effects carry their names
        std::vector<FittedRecording> fitted_on;
        for (std::size_t j = 0; j < R; ++j)
          if (j != k) fitted_on.push_back({&scorers[j], rest.size() > 1 ? own_of(fr, recs[j].name) : std::vector<AppliedEffect>{}});
        shares[k] = carry_no_harm(hardware_of(fr), fitted_on, o.carry);
        AppliedScore scored = scorers[k].score(shares[k].carried);
        rows[k] = std::move(scored.rows);
        carried[k] = std::move(scored.applied);
        if (o.search.progress) {
          const std::lock_guard<std::mutex> lock(done_m);
          ++done;
          char line[160];
          std::snprintf(line, sizeof line, "leave one out: %zu of %zu recordings done, about %.0f s left", done, R,
                        clock.left_s(done));
          o.search.progress(line);
        }
      } catch (const std::exception& e) {
        throw std::runtime_error("leaving out recording " + recs[k].name + ": " + e.what());
      }
    });
    for (std::size_t k = 0; k < R; ++k) {
      rep.leave_one_out.insert(rep.leave_one_out.end(), rows[k].begin(), rows[k].end());
      rep.carried[recs[k].name] = carried[k];
      rep.fold_carry[recs[k].name] = std::move(shares[k]);
    }
  }
  rep.problem = std::move(mp.problem);
  return rep;
}

std::vector<CalibrationReport> check_calibrations(const std::vector<std::pair<std::string, MultiSensorData>>& recordings,
                                                  const std::vector<std::vector<AppliedEffect>>& calibrations,
                                                  const MultiDiagnoseOptions& o) {
  if (recordings.empty()) throw ConfigError("calibration check: no recording");
  if (calibrations.empty()) throw ConfigError("calibration check: no calibration");
  const MultiProblemOptions po = problem_options(o);
  // each recording associated and its problem built once, for every calibration
  std::vector<AppliedScorer> scorers;
  std::map<std::string, ReferenceIntegrity> jumped;  // "<recording>/<target>"
  for (const auto& rec : recordings) {
    std::map<std::string, SensorAssociation> st;
    std::map<std::string, ReferenceIntegrity> jumps;
    const RecordingDetections rd{rec.first, associate(rec.second, o.association, st, &jumps)};
    for (auto& [t, x] : jumps) jumped[rec.first + "/" + t] = x;
    scorers.emplace_back(rd, scan_periods({&rec.second}), po);
  }
  std::vector<CalibrationReport> out(calibrations.size());
  for (auto& rep : out) rep.reference_jumps = jumped;
  for (std::size_t c = 0; c < calibrations.size(); ++c) {
    const std::vector<AppliedEffect>& effects = calibrations[c];
    const std::string which = calibrations.size() == 1 ? "calibration: " : "calibrations[" + std::to_string(c) + "]: ";
    CalibrationReport& rep = out[c];
    std::vector<char> used(effects.size(), 0);  // per effect: applied in some recording
    std::set<std::string> names;                // the catalogue's entry names
    for (std::size_t r = 0; r < recordings.size(); ++r) {
      AppliedScore scored;
      try {
        scored = scorers[r].score(effects);
      } catch (const ConfigError& e) {
        if (calibrations.size() == 1) throw;
        const std::string m = e.what(), lead = "calibration: ";
        throw ConfigError(which + (m.rfind(lead, 0) == 0 ? m.substr(lead.size()) : m));
      }
      rep.rows.insert(rep.rows.end(), scored.rows.begin(), scored.rows.end());
      rep.applied[recordings[r].first] = std::move(scored.applied);
      rep.recordings.push_back(recordings[r].first);
      for (std::size_t k = 0; k < effects.size(); ++k) used[k] |= scored.used[k];
      names.insert(scored.catalogue_names.begin(), scored.catalogue_names.end());
    }
    const std::vector<std::string> known(names.begin(), names.end());
    for (std::size_t k = 0; k < effects.size(); ++k) {
      const AppliedEffect& e = effects[k];
      const std::string label = e.key();
      if (!names.count(e.name))
        throw ConfigError(which + label + ": no catalogue entry is named '" + e.name + "'" + did_you_mean(e.name, known));
      // a boat or sensor these recordings do not have (a calibration from other recordings): named, not applied
      if (!used[k]) rep.absent.push_back(label);
    }
  }
  return out;
}

CalibrationReport check_calibration(const std::vector<std::pair<std::string, MultiSensorData>>& recordings,
                                    const std::vector<AppliedEffect>& effects, const MultiDiagnoseOptions& o) {
  return check_calibrations(recordings, {effects}, o).front();
}

nlohmann::ordered_json CalibrationReport::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = "multi_calibration";
  j["calibration"] = source;
  j["recordings"] = recordings;
  j["applied"] = applied;
  j["not_applied_own"] = own;
  j["not_applied_withheld"] = withheld;
  j["not_applied_findings"] = findings;
  j["not_applied_absent"] = absent;
  j["reference_jumps"] = reference_jumps_json(reference_jumps);
  j["reference_coverage"] = reference_coverage_json(reference_jumps);
  j["rows"] = nlohmann::ordered_json::array();
  for (const auto& x : rows)
    j["rows"].push_back({{"recording", x.recording}, {"pair", x.pair}, {"n", x.n}, {"nominal_rms", x.nominal_rms},
                         {"calibrated_rms", x.extended_rms}, {"unit", x.unit}});
  const LeaveOneOutSummary s = summarize(rows);
  j["summary"] = {{"min_n", s.min_n}, {"pairs", s.pairs}, {"geomean_ratio", s.geomean}, {"worst_ratio", s.worst}, {"worst", s.worst_key}};
  return j;
}

std::string CalibrationReport::text() const {
  std::ostringstream o;
  o << "  calibration " << source << "\n";
  o << reference_jumps_text(reference_jumps);
  if (!own.empty()) {
    o << "  not applied (one recording's own):";
    for (const auto& k : own) o << " " << k << ";";
    o << "\n";
  }
  if (!withheld.empty()) {
    o << "  not applied (withheld by the diagnosis's carry: at share 0, carrying it would make a pair of the recordings it was fitted "
         "on worse, or not taken by the fit it carries):";
    for (const auto& k : withheld) o << " " << k << ";";
    o << "\n";
  }
  if (!absent.empty()) {
    o << "  not applied (no observations in these recordings: another sensor or boat, or a misspelt one):";
    for (const auto& k : absent) o << " " << k << ";";
    o << "\n";
  }
  if (findings > 0)
    o << "  not applied: " << findings << " noise finding(s) and reference-track manoeuvre(s) (not corrections)\n";
  for (const auto& rec : recordings) {
    o << "  " << rec << ": applied";
    const auto& list = applied.at(rec);
    for (const auto& c : list) o << " " << c;
    if (list.empty()) o << " nothing (no effect of the calibration has observations here)";
    o << "\n";
  }
  for (const auto& x : rows)
    o << "  " << x.recording << " " << x.pair << ": RMS " << short_num(x.nominal_rms) << " -> " << short_num(x.extended_rms) << " "
      << x.unit << " (n " << x.n << ")\n";
  const LeaveOneOutSummary s = summarize(rows);
  o << "  calibrated / nominal RMS over " << s.pairs << " pairs with >= " << s.min_n << " detections: geometric mean "
    << short_num(s.geomean) << ", worst " << short_num(s.worst) << " (" << s.worst_key << ")\n";
  return o.str();
}

nlohmann::ordered_json CalibrationBatch::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = "multi_calibration_batch";
  j["calibration"] = source;
  j["calibrations"] = nlohmann::ordered_json::array();
  for (const auto& r : reports) j["calibrations"].push_back(r.to_json());
  return j;
}

std::string CalibrationBatch::text() const {
  std::ostringstream o;
  o << "  calibrations " << source << ": " << reports.size() << "\n";
  if (!reports.empty()) o << reference_jumps_text(reports.front().reference_jumps);  // the same recordings for each
  for (std::size_t c = 0; c < reports.size(); ++c) {
    const CalibrationReport& r = reports[c];
    // what was applied in any recording, each label once, in order of first appearance
    std::vector<std::string> applied;
    for (const auto& rec : r.recordings)
      for (const auto& x : r.applied.at(rec))
        if (std::find(applied.begin(), applied.end(), x) == applied.end()) applied.push_back(x);
    const LeaveOneOutSummary s = summarize(r.rows);
    o << "  calibrations[" << c << "]:";
    for (const auto& x : applied) o << " " << x;
    if (applied.empty()) o << " nothing applied";
    if (!r.absent.empty()) {
      o << " (not applied, no observations:";
      for (const auto& x : r.absent) o << " " << x;
      o << ")";
    }
    o << ": geometric mean " << short_num(s.geomean) << ", worst " << short_num(s.worst) << " (" << s.worst_key << ") over "
      << s.pairs << " pairs\n";
  }
  return o.str();
}

nlohmann::ordered_json MultiReport::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = "multi";
  j["association"] = nlohmann::ordered_json::object();
  for (const auto& [s, st] : association)
    j["association"][s] = {{"scans", st.scans}, {"detections", st.detections}, {"ambiguous_scans", st.ambiguous_scans},
                           {"associated", st.associated}, {"missed", st.missed}, {"ambiguous", st.ambiguous},
                           {"wide_pairs", st.wide_pairs}, {"gate_shift_bearing_rad", st.gate_shift_bearing_rad},
                           {"gate_shift_range_m", st.gate_shift_range_m}, {"gate_shift_bearing_se_rad", st.gate_shift_bearing_se_rad},
                           {"gate_shift_range_se_m", st.gate_shift_range_se_m}, {"gate_shift_clock_s", st.gate_shift_clock_s},
                           {"gate_shift_clock_se_s", st.gate_shift_clock_se_s}, {"clock_refused", st.clock_refused},
                           {"clock_refused_s", st.clock_refused_s}, {"shift_refused", st.shift_refused}, {"shift_rule", st.shift_rule},
                           {"shift_targets", st.shift_targets}, {"passes", st.passes}, {"rotation_period_s", st.rotation_period_s}};
  j["reference_jumps"] = reference_jumps_json(reference_jumps);
  j["reference_coverage"] = reference_coverage_json(reference_jumps);
  j["dropped_channels"] = dropped_channels;
  const nlohmann::ordered_json core = search_json(problem, result);
  j["effects"] = core["effects"];
  for (const auto& e : target_effects) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    x["scope"] = scope_json(e.scope);
    x["params"] = {"t_s", e.params[0], e.params[1]};
    x["estimate"] = {e.scan_value, e.estimate[0], e.estimate[1]};
    x["stderr"] = {e.scan_se, e.stderr_[0], e.stderr_[1]};
    x["evidence"] = evidence_json(e);
    x["confounded_with"] = nlohmann::ordered_json::array();
    x["note"] = "the reference track departs from constant velocity here (tested on the track itself)";
    j["effects"].push_back(x);
  }
  j["gain"] = nlohmann::ordered_json::object();
  for (const auto& [k, g] : gain)
    j["gain"][k] = {{"n", g.n}, {"nominal_rms", g.nominal_rms}, {"extended_rms", g.extended_rms}, {"unit", g.unit}};
  j["gain_window"] = recordings.empty() ? "fit on t < " + short_num(split_time_s) + " s, scored on t >= " + short_num(split_time_s) + " s"
                                        : "fit on the first " + short_num(100 * split_fraction) + " % of each recording, scored on the rest";
  j["gain_effects"] = result.holdout_effects;
  for (const char* k : {"noise", "offsets", "series_gain", "gain_fit", "limits_method", "detection_limits", "naming_limits", "fisher_limits", "injected_limits", "separation_limits", "scope_support", "unexplained", "refused", "familywise"}) j[k] = core[k];
  j["target_model"] = target_notes;
  j["scan_period_s"] = scan_period_s;
  j["carry"] = carry_json(carry);
  j["carry"]["alpha"] = carry_alpha;
  if (!recordings.empty()) {
    j["recordings"] = recordings;
    j["leave_one_out"] = nlohmann::ordered_json::array();
    for (const auto& x : leave_one_out)
      j["leave_one_out"].push_back({{"recording", x.recording}, {"pair", x.pair}, {"n", x.n}, {"nominal_rms", x.nominal_rms},
                                    {"extended_rms", x.extended_rms}, {"unit", x.unit}});
    j["leave_one_out_carried"] = carried;
    j["leave_one_out_carry"] = nlohmann::ordered_json::object();
    for (const auto& [rec, c] : fold_carry) j["leave_one_out_carry"][rec] = carry_json(c);
    const LeaveOneOutSummary s = summarize(leave_one_out);
    j["leave_one_out_summary"] = {{"min_n", s.min_n}, {"pairs", s.pairs}, {"geomean_ratio", s.geomean},
                                  {"worst_ratio", s.worst}, {"worst", s.worst_key}};
  }
  return j;
}

std::string MultiReport::text() const {
  std::ostringstream o;
  for (const auto& [s, st] : association) {
    o << "  sensor " << s << ": " << st.scans << " scans, " << st.detections << " detections, associated";
    for (const auto& [t, n] : st.associated) o << " " << t << ":" << n;
    o << " (ambiguous scans " << st.ambiguous_scans << ")";
    if (st.rotation_period_s > 0)
      o << ", each detection stamped at its own time: read as rotations of " << short_num(st.rotation_period_s) << " s";
    if (st.gate_shift_bearing_rad != 0 || st.gate_shift_range_m != 0 || st.gate_shift_clock_s != 0) {
      o << ", gates recentred by " << short_num(st.gate_shift_bearing_rad / kDegToRad) << " deg, "
        << short_num(st.gate_shift_range_m) << " m";
      if (st.gate_shift_clock_s != 0) o << " and a clock of " << short_num(st.gate_shift_clock_s) << " s";
      if (st.shift_rule == "targets")
        o << " (the sensor's common offset: the median over " << st.shift_targets << " targets' medians, +- "
          << short_num(st.gate_shift_bearing_se_rad / kDegToRad) << " deg, " << short_num(st.gate_shift_range_se_m) << " m; "
          << st.passes << " pass" << (st.passes == 1 ? "" : "es") << ")";
      else
        o << " (the sensor's common offset beyond its gate, fitted on " << st.wide_pairs << " unambiguous pairs, then on each pass's; "
          << st.passes << " pass" << (st.passes == 1 ? "" : "es") << ")";
      if (!st.clock_refused.empty())
        o << "; a clock of " << short_num(st.clock_refused_s) << " s on the pooled pairs left out of the gates: " << st.clock_refused;
    } else if (!st.shift_refused.empty()) {
      o << ", gates left on the prediction: " << st.shift_refused;
    } else if (st.shift_rule == "targets") {
      o << ", gates centred on the prediction (no common offset over " << st.shift_targets << " targets)";
    }
    o << "\n";
  }
  o << reference_jumps_text(reference_jumps);
  for (const auto& d : dropped_channels) o << "  not diagnosed (fewer than 10 associated detections): " << d << "\n";
  o << search_text(problem, result);
  for (const auto& e : target_effects)
    o << "  EFFECT   target_maneuver [target " << e.scope.target << "]: at t = " << short_num(e.scan_value) << " +- "
      << short_num(e.scan_se) << " s, dv = (" << short_num(e.estimate[0]) << " +- " << short_num(e.stderr_[0]) << ", "
      << short_num(e.estimate[1]) << " +- " << short_num(e.stderr_[1]) << ") m/s\n";
  for (const auto& n : target_notes) o << "  target   " << n << "\n";
  for (const auto& [k, g] : gain)
    o << "  gain " << k << ": RMS " << short_num(g.nominal_rms) << " -> " << short_num(g.extended_rms) << " " << g.unit
      << " (n " << g.n << ")\n";
  if (recordings.empty())
    o << "  gain window: fit on t < " << short_num(split_time_s) << " s with";
  else
    o << "  gain window: fit on the first " << short_num(100 * split_fraction) << " % of each recording with";
  o << gain_fit_text(problem, result);
  if (result.holdout_effects.empty()) o << " no effect (none named, or none determined by the window)";
  o << "\n";
  if (!carry.fitted.empty()) {
    o << "  carried to another recording (--apply; hardware of the fit at alpha " << short_num(carry_alpha) << "), ";
    if (carry.tolerance > 0)
      o << "each hardware value at the share (a grid in [0, 1]) with the lowest error on these recordings that leaves none of their "
           "pairs worse than " << short_num(carry.tolerance) << " x its error with its recording's own effects removed (geometric mean " << short_num(carry.chosen.geomean) << ", worst " << short_num(carry.chosen.worst)
        << "; with every value whole " << short_num(carry.whole.geomean) << ", worst " << short_num(carry.whole.worst) << " ("
        << carry.whole.worst_key << ")), in the catalogue's units:\n";
    else
      o << "every hardware value whole (--carry-tolerance 0), in the catalogue's units:\n";
    o << carry_text(carry, "    ");
  }
  if (!recordings.empty()) {
    for (const auto& [rec, list] : carried) {
      o << "  leave out " << rec << ": carried";
      for (const auto& c : list) o << " " << c;
      if (list.empty()) o << " nothing (no hardware effect named on the others that applies to it, or none kept by the carry rule)";
      const auto it = fold_carry.find(rec);
      if (it != fold_carry.end())
        for (std::size_t k = 0; k < it->second.fitted.size(); ++k)
          if (it->second.share[k] < 1) {
            const AppliedEffect& e = it->second.fitted[k];
            o << "; " << e.key() << " at share " << short_num(it->second.share[k]);
          }
      o << "\n";
    }
    for (const auto& x : leave_one_out)
      o << "  left out " << x.recording << " " << x.pair << ": RMS " << short_num(x.nominal_rms) << " -> "
        << short_num(x.extended_rms) << " " << x.unit << " (n " << x.n << ")\n";
    const LeaveOneOutSummary s = summarize(leave_one_out);
    o << "  leave one recording out: " << s.pairs << " pairs with >= " << s.min_n << " detections, extended / nominal RMS geometric mean "
      << short_num(s.geomean) << ", worst " << short_num(s.worst) << " (" << s.worst_key << ")\n";
  }
  return o.str();
}

std::vector<CsvColumnDoc> MultiReport::residuals_columns() {
  return {{"t_s", "s", "detection time, the recording's time scale"},
          {"sensor", "", "sensor name"},
          {"target", "", "target name (the reference track the detection is associated with)"},
          {"quantity", "", "what the residual is of: range or bearing"},
          {"residual", "m or rad", "measured minus predicted from the reference (m for a range, rad for a bearing)"},
          {"extended_fit", "m or rad", "the extended model's fit to the residual (the named effects), in the residual's unit"},
          {"estimation", "", "1 if in the gain's estimation window (fitted), 0 if in the scored window"},
          {"outlier", "", "1 if the noise identification flags the detection an outlier, else 0"},
          {"recording", "", "recording name (several recordings diagnosed together); empty for one recording"}};
}

void MultiReport::write_residuals_csv(const std::string& file) const {
  const auto columns = residuals_columns();
  std::ostringstream f;
  f << csv_header(columns);
  std::vector<std::size_t> pos(problem.channels.size(), 0);
  char b[256];
  for (std::size_t i = 0; i < problem.size(); ++i) {
    const auto c = static_cast<std::size_t>(problem.channel[i]);
    const Channel& ch = problem.channels[c];
    const auto& flags = result.noise[c].fit.outlier;
    const bool out = pos[c] < flags.size() && flags[pos[c]];
    ++pos[c];
    // pooled channels are named "<recording>/<sensor>:<target>:<quantity>"
    const auto slash = ch.name.find('/');
    const std::string rec = slash == std::string::npos ? "" : ch.name.substr(0, slash);
    std::snprintf(b, sizeof b, "%.6f,%s,%s,%s,%.9g,%.9g,%d,%d,%s\n", problem.t_s[i], ch.sensor.c_str(), ch.target.c_str(),
                  ch.unit == "m" ? "range" : "bearing", problem.y[i], result.effect_fit(static_cast<Eigen::Index>(i)),
                  problem.estimation[i] ? 1 : 0, out ? 1 : 0, rec.c_str());
    f << b;
  }
  if (!f.flush()) throw ConfigError("cannot write " + file + " (disk full?)");
  write_file_atomic(file, f.str());
  write_csv_units(file, columns);
}

}  // namespace rnav
