#include "uav_realizations.hpp"

#include "atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace rnav {

namespace {

// 9 significant digits (the aggregates recomputed from the rows agree to ~1e-9 relative).
std::string g9(double x) { return significant(x, 9); }

}  // namespace

std::string uav_realizations_header() {
  return "realization,estimator,t_s,at_eval,pos_err_north_m,pos_err_east_m,vel_err_north_mps,vel_err_east_mps,"
         "pos_err_m,vel_err_mps,sigma_pos_north_m,sigma_pos_east_m,sigma_vel_north_mps,sigma_vel_east_mps,"
         "nees,updated,nis\n";
}

std::string uav_realization_rows(const UavScenario& sc, long realization, const TmaRealization& r) {
  std::set<std::size_t> eval;
  for (const auto& [name, i] : samples_at_eval(r, sc.utime(to_us(sc.eval_time_s())))) eval.insert(i);
  const std::int64_t step_us = to_us(sc.logger.realizations_step_s);
  std::vector<std::size_t> order(r.samples.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const auto& x = r.samples[a];
    const auto& y = r.samples[b];
    return x.estimator != y.estimator ? x.estimator < y.estimator : x.utime < y.utime;
  });
  std::string out;
  std::string last_estimator;
  std::int64_t last_bin = 0;
  for (const std::size_t i : order) {
    const TmaSample& s = r.samples[i];
    const std::int64_t t_us = s.utime - sc.runner.epoch_utime;
    const bool at_eval = eval.count(i) > 0;
    // the first frame of each interval [k step, (k+1) step): any sensor period gives a row per step
    const std::int64_t bin = step_us > 0 ? (t_us >= 0 ? t_us / step_us : -1 - (-1 - t_us) / step_us) : t_us;
    const bool first_in_bin = s.estimator != last_estimator || bin != last_bin;
    last_estimator = s.estimator;
    last_bin = bin;
    if (!at_eval && !first_in_bin) continue;
    out += std::to_string(realization) + "," + s.estimator + "," + fixed(t_us * 1e-6, 3) + "," + (at_eval ? "1" : "0");
    for (double e : s.err) out += "," + g9(e);
    out += "," + g9(std::sqrt(s.pos_err2)) + "," + g9(std::sqrt(s.vel_err2));
    for (double v : s.sigma) out += "," + g9(v);
    out += "," + g9(s.nees) + "," + (s.updated ? "1" : "0") + "," + g9(s.updated ? s.nis : 0.0) + "\n";
  }
  return out;
}

}  // namespace rnav
