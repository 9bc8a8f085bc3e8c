#include "loggers/uav_stats.hpp"

#include "common/io/atomic_file.hpp"
#include "loggers/realization_set.hpp"
#include "loggers/state_json.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rnav {


std::pair<double, double> chi2_mean_band(long n, int dof, double z) {
  // chi2(nu) quantile ~ nu (1 - 2/(9 nu) + z sqrt(2/(9 nu)))^3; the mean of n draws of
  // chi2(dof) is chi2(n dof) / n.
  const double nu = static_cast<double>(n) * dof, a = 2.0 / (9.0 * nu);
  auto q = [&](double zz) { return nu * std::pow(1 - a + zz * std::sqrt(a), 3) / n; };
  return {q(-z), q(z)};
}

std::map<std::string, std::size_t> samples_at_eval(const TmaRealization& r, std::int64_t eval_utime) {
  std::map<std::string, std::size_t> last;
  for (std::size_t i = 0; i < r.samples.size(); ++i)
    if (r.samples[i].utime <= eval_utime) last[r.samples[i].estimator] = i;
  return last;
}

UavStats::UavStats(const UavStatsSetup& sc) : sc_(sc) {}

void UavStats::add_to(MatSum& s, const tma::Mat4& m) {
  for (int i = 0; i < 16; ++i) s[i].add(m.data()[i]);
}

tma::Mat4 UavStats::value(const MatSum& s) {
  tma::Mat4 m;
  for (int i = 0; i < 16; ++i) m.data()[i] = s[i].value();
  return m;
}

void UavStats::add_realization(const TmaRealization& r, long realization) {
  if (realization < 0) realization = held_.empty() ? 0 : *held_.rbegin() + 1;
  if (held_.count(realization)) throw std::runtime_error("realization " + std::to_string(realization) + " added twice");
  if (r.first_utime < 0) throw std::runtime_error("realization without any detection: no estimate");
  if (first_utime_ >= 0 && r.first_utime != first_utime_)
    throw std::runtime_error("realizations disagree on the first detection time: the PCRB's prior "
                             "would differ (detections must follow the deterministic geometry)");
  std::map<std::string, const TmaSample*> last;  // last sample at or before eval per estimator
  for (const auto& [name, i] : samples_at_eval(r, sc_.utime(to_us(sc_.eval_time_s())))) last[name] = &r.samples[i];
  range_min_m_ = std::min(range_min_m_, r.range_min_m);
  range_max_m_ = std::max(range_max_m_, r.range_max_m);
  range_sum_m_.add(r.range_sum_m);
  range_n_ += r.range_n;
  inside_orbit_runs_ += r.range_n > 0 && r.range_max_m <= 2 * sc_.uav.radius_m;
  for (const auto& s : r.samples) {
    auto& a = by_time_[s.estimator][s.utime];
    ++a.n;
    a.pos2.add(s.pos_err2);
    a.vel2.add(s.vel_err2);
    a.nees.add(s.nees);
    if (s.updated) {
      ++a.n_upd;
      a.nis.add(s.nis);
    }
  }
  for (const auto& [name, s] : last) {
    auto& f = final_[name];
    ++f.n;
    const bool div = !std::isfinite(s->pos_err2) || std::sqrt(s->pos_err2) > sc_.logger.diverge_pos_m;
    f.diverged += div;
    f.pos2.add(s->pos_err2);
    f.vel2.add(s->vel_err2);
    f.nees.add(s->nees);
  }
  for (const auto& [t, J] : r.info) add_to(info_sum_[t], J);
  add_to(J0_sum_, r.J0);
  first_utime_ = r.first_utime;
  held_.insert(realization);
  std::set<std::int64_t> frames(frames_.begin(), frames_.end());
  for (const auto& s : r.samples) frames.insert(s.utime);
  frames_.assign(frames.begin(), frames.end());
  ++n_;
}

void UavStats::pcrb(std::map<std::int64_t, double>* pos, std::map<std::int64_t, double>* vel) const {
  if (n_ == 0) return;
  // One recursion with the ensemble-averaged information E[H^T R^-1 H] per frame.
  tma::TmaPcrb b(value(J0_sum_) / static_cast<double>(n_));
  std::int64_t t_prev = first_utime_;
  for (std::int64_t t : frames_) {
    if (t < first_utime_) continue;
    b.predict((t - t_prev) * 1e-6, sc_.tma.q_m2ps3);
    t_prev = t;
    if (t != first_utime_) {
      auto it = info_sum_.find(t);
      if (it != info_sum_.end()) {
        tma::Mat4 J = b.information() + value(it->second) / static_cast<double>(n_);
        b = tma::TmaPcrb(J);
      }
    }
    if (pos) (*pos)[t] = b.pos_rmse_m();
    if (vel) (*vel)[t] = b.vel_rmse_mps();
  }
}

std::map<std::int64_t, double> UavStats::pcrb_pos() const {
  std::map<std::int64_t, double> m;
  pcrb(&m, nullptr);
  return m;
}

std::map<std::int64_t, double> UavStats::pcrb_vel() const {
  std::map<std::int64_t, double> m;
  pcrb(nullptr, &m);
  return m;
}

namespace {

// A FinalAcc's sums, rounded once.
struct Final {
  explicit Final(const UavStats::FinalAcc& a)
      : n(a.n), diverged(a.diverged), pos2(a.pos2.value()), vel2(a.vel2.value()), nees(a.nees.value()) {}
  long n, diverged;
  double pos2, vel2, nees;
};

}  // namespace

std::vector<CsvColumnDoc> UavStats::stats_time_columns() const {
  std::vector<CsvColumnDoc> c{
      {"t_s", "s", "frame time since sim time 0 (runner.epoch_utime)"},
      {"pcrb_pos_m", "m", "posterior Cramer-Rao bound on the object's horizontal position RMSE"},
      {"pcrb_vel_mps", "m/s", "posterior Cramer-Rao bound on the object's horizontal velocity RMSE"},
      {"nees_band_lo", "", "lower edge of the 95 % band of the mean NEES (4 dof) over the realizations"},
      {"nees_band_hi", "", "upper edge of the 95 % band of the mean NEES (4 dof) over the realizations"},
      {"nis_band_lo", "", "lower edge of the 95 % band of the mean NIS (1 dof) over the realizations"},
      {"nis_band_hi", "", "upper edge of the 95 % band of the mean NIS (1 dof) over the realizations"}};
  for (const auto& [name, _] : by_time_) {
    c.push_back({name + "_n", "", "realizations with an estimate of " + name + " at this time"});
    c.push_back({name + "_rmse_pos_m", "m", name + "'s horizontal position error (north, east), RMS over the realizations"});
    c.push_back({name + "_rmse_vel_mps", "m/s", name + "'s horizontal velocity error, RMS over the realizations"});
    c.push_back({name + "_nees_mean", "", name + "'s NEES (4 dof), mean over the realizations"});
    c.push_back({name + "_nis_mean", "", name + "'s NIS (1 dof), mean over the realizations whose estimate used a bearing at this time"});
  }
  return c;
}

void UavStats::write(const std::string& dir, std::int64_t seed) const {
  if (n_ == 0) throw std::runtime_error("no complete realization to write");
  std::filesystem::create_directories(dir);
  std::map<std::int64_t, double> pp, pv;
  pcrb(&pp, &pv);
  const auto nees_band = chi2_mean_band(n_, 4), nis_band = chi2_mean_band(n_, 1);

  const auto columns = stats_time_columns();
  std::ostringstream ts;
  ts << csv_header(columns);
  for (std::int64_t t : frames_) {
    if (!pp.count(t)) continue;
    ts << fixed((t - sc_.runner.epoch_utime) * 1e-6, 3) << "," << fixed(pp.at(t)) << "," << fixed(pv.at(t))
       << "," << fixed(nees_band.first) << "," << fixed(nees_band.second) << "," << fixed(nis_band.first)
       << "," << fixed(nis_band.second);
    for (const auto& [name, m] : by_time_) {
      static const Acc empty{};
      const auto it = m.find(t);
      const Acc& a = it == m.end() ? empty : it->second;
      ts << "," << a.n << "," << fixed(a.n ? std::sqrt(a.pos2.value() / a.n) : NAN) << ","
         << fixed(a.n ? std::sqrt(a.vel2.value() / a.n) : NAN) << "," << fixed(a.n ? a.nees.value() / a.n : NAN) << ","
         << fixed(a.n_upd ? a.nis.value() / a.n_upd : NAN);
    }
    ts << "\n";
  }
  write_file_atomic(dir, "uav_stats_time.csv", ts.str());
  write_csv_units(dir, "uav_stats_time.csv", columns);

  // The PCRB at the evaluation time: the last frame at or before it.
  const std::int64_t eval = sc_.utime(to_us(sc_.eval_time_s()));
  double pcrb_pos = NAN, pcrb_vel = NAN;
  for (const auto& [t, v] : pp)
    if (t <= eval) {
      pcrb_pos = v;
      pcrb_vel = pv.at(t);
    }
  nlohmann::ordered_json j;
  j["realizations"] = n_;
  j["seed"] = seed;
  j["eval_time_s"] = sc_.eval_time_s();
  j["guidance"] = sc_.uav.guidance;
  j["object_range_m"] = {{"min", range_min_m_}, {"mean", range_sum_m_.value() / std::max(1L, range_n_)}, {"max", range_max_m_}};
  j["object_inside_orbit_runs"] = inside_orbit_runs_;
  j["pcrb_pos_m"] = pcrb_pos;
  j["pcrb_vel_mps"] = pcrb_vel;
  j["estimators"] = nlohmann::ordered_json::object();
  for (const auto& [name, acc] : final_) {
    const Final f(acc);
    auto& e = j["estimators"][name];
    e["rmse_pos_m"] = std::sqrt(f.pos2 / f.n);
    e["rmse_vel_mps"] = std::sqrt(f.vel2 / f.n);
    e["rmse_pos_over_pcrb"] = std::sqrt(f.pos2 / f.n) / pcrb_pos;
    e["nees_mean"] = f.nees / f.n;
    e["nees_band"] = {nees_band.first, nees_band.second};
    e["nees_within_band"] = f.nees / f.n >= nees_band.first && f.nees / f.n <= nees_band.second;
    e["diverged"] = f.diverged;
    e["runs"] = f.n;
  }
  write_file_atomic(dir, "summary.json", j.dump(2) + "\n");
  std::ostringstream t;
  t << "Azimuth-only estimation: " << n_ << " realizations, seed " << seed << ", figures at t = "
    << fixed(sc_.eval_time_s(), 1) << " s"
    << (std::abs(sc_.eval_time_s() - 2 * sc_.orbit_period_s()) < 1e-6 ? " (two orbits)" : "") << "\n";
  t << "PCRB position RMSE " << fixed(pcrb_pos, 3) << " m, velocity RMSE " << fixed(pcrb_vel, 4)
    << " m/s\n";
  t << "guidance " << sc_.uav.guidance << ": UAV-object range " << fixed(range_min_m_, 1) << " ... "
    << fixed(range_max_m_, 1) << " m (mean " << fixed(range_sum_m_.value() / std::max(1L, range_n_), 1) << "), object inside the orbit (range <= "
    << fixed(2 * sc_.uav.radius_m, 0) << " m throughout) in " << inside_orbit_runs_ << "/" << n_ << " runs\n";
  t << "estimator  RMSE pos [m]  /PCRB   RMSE vel [m/s]  NEES mean  95% band          diverged\n";
  for (const auto& [name, acc] : final_) {
    const Final f(acc);
    char b[256];
    std::snprintf(b, sizeof b, "%-9s  %12.3f  %6.3f  %14.4f  %9.3f  [%5.2f, %5.2f]  %s  %ld/%ld\n",
                  name.c_str(), std::sqrt(f.pos2 / f.n), std::sqrt(f.pos2 / f.n) / pcrb_pos,
                  std::sqrt(f.vel2 / f.n), f.nees / f.n, nees_band.first, nees_band.second,
                  (f.nees / f.n >= nees_band.first && f.nees / f.n <= nees_band.second) ? "in " : "OUT",
                  f.diverged, f.n);
    t << b;
  }
  write_file_atomic(dir, "summary.txt", t.str());
  write_file_atomic(dir, "ensemble_state.json", state(seed).dump() + "\n");
}

}  // namespace rnav

namespace rnav {

namespace {

using J = nlohmann::ordered_json;

using state_json::exact_sum_member;
using state_json::exact_text;
using state_json::int_member;
using state_json::member;

double read17(const nlohmann::json& j, const std::string& what) { return state_json::read_exact(j, what, false); }

}  // namespace

nlohmann::ordered_json UavStats::state(std::int64_t seed) const {
  J j;
  j["kind"] = "uav";
  j["format"] = 1;
  j["seed"] = seed;
  j["realizations"] = n_;
  j["held"] = realization_intervals(held_);
  j["first_utime"] = first_utime_;
  j["frames"] = frames_;
  j["range"] = {{"min", exact_text(range_min_m_)}, {"max", exact_text(range_max_m_)}, {"sum", range_sum_m_.to_text()},
                {"n", range_n_}, {"inside_orbit_runs", inside_orbit_runs_}};
  j["by_time"] = J::object();
  for (const auto& [name, m] : by_time_) {
    auto& rows = j["by_time"][name] = J::array();
    for (const auto& [t, a] : m)
      rows.push_back({{"utime", t}, {"n", a.n}, {"n_upd", a.n_upd}, {"pos2", a.pos2.to_text()}, {"vel2", a.vel2.to_text()},
                      {"nees", a.nees.to_text()}, {"nis", a.nis.to_text()}});
  }
  j["final"] = J::object();
  for (const auto& [name, f] : final_)
    j["final"][name] = {{"n", f.n}, {"diverged", f.diverged}, {"pos2", f.pos2.to_text()}, {"vel2", f.vel2.to_text()},
                        {"nees", f.nees.to_text()}};
  const auto mat = [](const MatSum& s) {
    J a = J::array();
    for (const auto& e : s) a.push_back(e.to_text());
    return a;
  };
  j["info"] = J::array();
  for (const auto& [t, s] : info_sum_) j["info"].push_back({{"utime", t}, {"sum", mat(s)}});
  j["J0"] = mat(J0_sum_);
  return j;
}

void UavStats::merge_state(const nlohmann::json& j, std::int64_t seed, const std::string& what) {
  if (member(j, "kind", what) != "uav" || member(j, "format", what) != 1)
    throw std::invalid_argument(what + ": not an azimuth-only ensemble state (format 1)");
  if (member(j, "seed", what) != seed)
    throw std::invalid_argument(what + ": seed " + member(j, "seed", what).dump() + ", the merged ensemble's is " + std::to_string(seed));
  // Parse into a UavStats of its own first: a rejected shard changes nothing here.
  UavStats o(sc_);
  o.n_ = int_member<long>(j, "realizations", what);
  o.held_ = rnav::realization_set(member(j, "held", what), what);
  for (long r : o.held_)
    if (held_.count(r)) throw std::invalid_argument(what + ": realization " + std::to_string(r) + " is already in the merged ensemble");
  if (static_cast<long>(o.held_.size()) != o.n_)
    throw std::invalid_argument(what + ": " + std::to_string(o.n_) + " realizations but 'held' names " + std::to_string(o.held_.size()));
  o.first_utime_ = int_member<std::int64_t>(j, "first_utime", what);
  if (n_ > 0 && o.n_ > 0 && o.first_utime_ != first_utime_)
    throw std::invalid_argument(what + ": first detection at utime " + std::to_string(o.first_utime_) +
                                ", the merged ensemble's at " + std::to_string(first_utime_) + " (the PCRB's prior would differ)");
  o.frames_ = member(j, "frames", what).get<std::vector<std::int64_t>>();
  const auto& rg = member(j, "range", what);
  o.range_min_m_ = read17(member(rg, "min", what), what + " range.min");
  o.range_max_m_ = read17(member(rg, "max", what), what + " range.max");
  o.range_sum_m_ = exact_sum_member(rg, "sum", what + " range");
  o.range_n_ = int_member<long>(rg, "n", what + " range");
  o.inside_orbit_runs_ = int_member<long>(rg, "inside_orbit_runs", what + " range");
  for (const auto& [name, rows] : member(j, "by_time", what).items())
    for (const auto& r : rows) {
      const std::string w = what + " by_time." + name;
      auto& a = o.by_time_[name][int_member<std::int64_t>(r, "utime", w)];
      a.n = int_member<long>(r, "n", w);
      a.n_upd = int_member<long>(r, "n_upd", w);
      a.pos2 = exact_sum_member(r, "pos2", w);
      a.vel2 = exact_sum_member(r, "vel2", w);
      a.nees = exact_sum_member(r, "nees", w);
      a.nis = exact_sum_member(r, "nis", w);
    }
  for (const auto& [name, f] : member(j, "final", what).items()) {
    const std::string w = what + " final." + name;
    auto& a = o.final_[name];
    a.n = int_member<long>(f, "n", w);
    a.diverged = int_member<long>(f, "diverged", w);
    a.pos2 = exact_sum_member(f, "pos2", w);
    a.vel2 = exact_sum_member(f, "vel2", w);
    a.nees = exact_sum_member(f, "nees", w);
  }
  const auto mat = [&](const nlohmann::json& a, const std::string& w) {
    if (!a.is_array() || a.size() != 16) throw std::invalid_argument(w + ": expected 16 exact sums");
    MatSum s;
    for (int i = 0; i < 16; ++i) {
      if (!a[i].is_string()) throw std::invalid_argument(w + ": expected exact sums as text");
      s[i] = ExactSum::from_text(a[i].get<std::string>(), w);
    }
    return s;
  };
  for (const auto& e : member(j, "info", what)) o.info_sum_[int_member<std::int64_t>(e, "utime", what + " info")] = mat(member(e, "sum", what), what + " info");
  o.J0_sum_ = mat(member(j, "J0", what), what + " J0");
  // Every check passed: add.
  for (auto& [name, m] : o.by_time_)
    for (auto& [t, a] : m) {
      auto& b = by_time_[name][t];
      b.n += a.n;
      b.n_upd += a.n_upd;
      b.pos2.merge(a.pos2);
      b.vel2.merge(a.vel2);
      b.nees.merge(a.nees);
      b.nis.merge(a.nis);
    }
  for (auto& [name, a] : o.final_) {
    auto& b = final_[name];
    b.n += a.n;
    b.diverged += a.diverged;
    b.pos2.merge(a.pos2);
    b.vel2.merge(a.vel2);
    b.nees.merge(a.nees);
  }
  for (auto& [t, s] : o.info_sum_)
    for (int i = 0; i < 16; ++i) info_sum_[t][i].merge(s[i]);
  for (int i = 0; i < 16; ++i) J0_sum_[i].merge(o.J0_sum_[i]);
  std::set<std::int64_t> frames(frames_.begin(), frames_.end());
  frames.insert(o.frames_.begin(), o.frames_.end());
  frames_.assign(frames.begin(), frames.end());
  if (o.n_ > 0) first_utime_ = o.first_utime_;
  range_min_m_ = std::min(range_min_m_, o.range_min_m_);
  range_max_m_ = std::max(range_max_m_, o.range_max_m_);
  range_sum_m_.merge(o.range_sum_m_);
  range_n_ += o.range_n_;
  inside_orbit_runs_ += o.inside_orbit_runs_;
  held_.insert(o.held_.begin(), o.held_.end());
  n_ += o.n_;
}

}  // namespace rnav
