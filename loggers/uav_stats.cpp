#include "uav_stats.hpp"

#include "atomic_file.hpp"

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

UavStats::UavStats(const UavScenario& sc) : sc_(sc) {}

void UavStats::add_realization(const TmaRealization& r) {
  if (r.first_utime < 0) throw std::runtime_error("realization without any detection: no estimate");
  if (first_utime_ >= 0 && r.first_utime != first_utime_)
    throw std::runtime_error("realizations disagree on the first detection time: the PCRB's prior "
                             "would differ (detections must follow the deterministic geometry)");
  std::map<std::string, const TmaSample*> last;  // last sample at or before eval per estimator
  for (const auto& [name, i] : samples_at_eval(r, sc_.utime(to_us(sc_.eval_time_s())))) last[name] = &r.samples[i];
  range_min_m_ = std::min(range_min_m_, r.range_min_m);
  range_max_m_ = std::max(range_max_m_, r.range_max_m);
  range_sum_m_ += r.range_sum_m;
  range_n_ += r.range_n;
  inside_orbit_runs_ += r.range_n > 0 && r.range_max_m <= 2 * sc_.uav.radius_m;
  for (const auto& s : r.samples) {
    auto& a = by_time_[s.estimator][s.utime];
    ++a.n;
    a.pos2 += s.pos_err2;
    a.vel2 += s.vel_err2;
    a.nees += s.nees;
    if (s.updated) {
      ++a.n_upd;
      a.nis += s.nis;
    }
  }
  for (const auto& [name, s] : last) {
    auto& f = final_[name];
    ++f.n;
    const bool div = !std::isfinite(s->pos_err2) || std::sqrt(s->pos_err2) > sc_.logger.diverge_pos_m;
    f.diverged += div;
    f.pos2 += s->pos_err2;
    f.vel2 += s->vel_err2;
    f.nees += s->nees;
  }
  for (const auto& [t, J] : r.info) {
    auto it = info_sum_.find(t);
    if (it == info_sum_.end()) info_sum_.emplace(t, J);
    else it->second += J;
  }
  J0_sum_ += r.J0;
  first_utime_ = r.first_utime;
  std::set<std::int64_t> frames(frames_.begin(), frames_.end());
  for (const auto& s : r.samples) frames.insert(s.utime);
  frames_.assign(frames.begin(), frames.end());
  ++n_;
}

void UavStats::pcrb(std::map<std::int64_t, double>* pos, std::map<std::int64_t, double>* vel) const {
  if (n_ == 0) return;
  // One recursion with the ensemble-averaged information E[H^T R^-1 H] per frame.
  tma::TmaPcrb b(J0_sum_ / static_cast<double>(n_));
  std::int64_t t_prev = first_utime_;
  for (std::int64_t t : frames_) {
    if (t < first_utime_) continue;
    b.predict((t - t_prev) * 1e-6, sc_.tma.q_m2ps3);
    t_prev = t;
    if (t != first_utime_) {
      auto it = info_sum_.find(t);
      if (it != info_sum_.end()) {
        tma::Mat4 J = b.information() + it->second / static_cast<double>(n_);
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

void UavStats::write(const std::string& dir, std::int64_t seed) const {
  if (n_ == 0) throw std::runtime_error("no complete realization to write");
  std::filesystem::create_directories(dir);
  std::map<std::int64_t, double> pp, pv;
  pcrb(&pp, &pv);
  const auto nees_band = chi2_mean_band(n_, 4), nis_band = chi2_mean_band(n_, 1);

  std::ostringstream ts;
  ts << "t_s,pcrb_pos_m,pcrb_vel_mps,nees_band_lo,nees_band_hi,nis_band_lo,nis_band_hi";
  for (const auto& [name, _] : by_time_)
    ts << "," << name << "_n," << name << "_rmse_pos_m," << name << "_rmse_vel_mps," << name
       << "_nees_mean," << name << "_nis_mean";
  ts << "\n";
  for (std::int64_t t : frames_) {
    if (!pp.count(t)) continue;
    ts << fixed((t - sc_.runner.epoch_utime) * 1e-6, 3) << "," << fixed(pp.at(t)) << "," << fixed(pv.at(t))
       << "," << fixed(nees_band.first) << "," << fixed(nees_band.second) << "," << fixed(nis_band.first)
       << "," << fixed(nis_band.second);
    for (const auto& [name, m] : by_time_) {
      const auto it = m.find(t);
      const Acc a = it == m.end() ? Acc{} : it->second;
      ts << "," << a.n << "," << fixed(a.n ? std::sqrt(a.pos2 / a.n) : NAN) << ","
         << fixed(a.n ? std::sqrt(a.vel2 / a.n) : NAN) << "," << fixed(a.n ? a.nees / a.n : NAN) << ","
         << fixed(a.n_upd ? a.nis / a.n_upd : NAN);
    }
    ts << "\n";
  }
  write_file_atomic(dir, "uav_stats_time.csv", ts.str());

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
  j["object_range_m"] = {{"min", range_min_m_}, {"mean", range_sum_m_ / std::max(1L, range_n_)}, {"max", range_max_m_}};
  j["object_inside_orbit_runs"] = inside_orbit_runs_;
  j["pcrb_pos_m"] = pcrb_pos;
  j["pcrb_vel_mps"] = pcrb_vel;
  j["estimators"] = nlohmann::ordered_json::object();
  for (const auto& [name, f] : final_) {
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
    << fixed(range_max_m_, 1) << " m (mean " << fixed(range_sum_m_ / std::max(1L, range_n_), 1) << "), object inside the orbit (range <= "
    << fixed(2 * sc_.uav.radius_m, 0) << " m throughout) in " << inside_orbit_runs_ << "/" << n_ << " runs\n";
  t << "estimator  RMSE pos [m]  /PCRB   RMSE vel [m/s]  NEES mean  95% band          diverged\n";
  for (const auto& [name, f] : final_) {
    char b[256];
    std::snprintf(b, sizeof b, "%-9s  %12.3f  %6.3f  %14.4f  %9.3f  [%5.2f, %5.2f]  %s  %ld/%ld\n",
                  name.c_str(), std::sqrt(f.pos2 / f.n), std::sqrt(f.pos2 / f.n) / pcrb_pos,
                  std::sqrt(f.vel2 / f.n), f.nees / f.n, nees_band.first, nees_band.second,
                  (f.nees / f.n >= nees_band.first && f.nees / f.n <= nees_band.second) ? "in " : "OUT",
                  f.diverged, f.n);
    t << b;
  }
  write_file_atomic(dir, "summary.txt", t.str());
}

}  // namespace rnav
