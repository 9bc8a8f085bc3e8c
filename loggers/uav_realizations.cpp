#include "loggers/uav_realizations.hpp"

#include "common/io/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace rnav {

namespace {

// 9 significant digits (the aggregates recomputed from the rows agree to ~1e-9 relative).
std::string g9(double x) { return significant(x, 9); }

}  // namespace

std::vector<CsvColumnDoc> uav_realizations_columns() {
  // The state's components in TmaSample's order (err, sigma): north, east [m], v_north, v_east [m/s].
  struct Component {
    const char* quantity;  // pos, vel
    const char* axis;      // north, east
    const char* suffix;    // the name's unit suffix
    const char* unit;
    const char* text;
  };
  constexpr Component kState[4] = {{"pos", "north", "m", "m", "object position north"},
                                   {"pos", "east", "m", "m", "object position east"},
                                   {"vel", "north", "mps", "m/s", "object velocity north"},
                                   {"vel", "east", "mps", "m/s", "object velocity east"}};
  const std::string in_F = " (local level frame F at the scenario origin)";
  const auto tail = [](const Component& k) { return std::string(k.axis) + "_" + k.suffix; };
  std::vector<CsvColumnDoc> c{
      {"realization", "", "realization index in the ensemble"},
      {"estimator", "", "estimator name (UAV_TMA's estimator)"},
      {"t_s", "s", "frame time since sim time 0 (runner.epoch_utime)"},
      {"at_eval", "",
       "1 on the row summary.json takes its figures from (the last frame at or before logger.eval_time_s), else 0"}};
  for (const auto& k : kState)
    c.push_back({std::string(k.quantity) + "_err_" + tail(k), k.unit, std::string("estimate minus truth, ") + k.text + in_F});
  c.push_back({"pos_err_m", "m", "horizontal position error, norm of (north, east)"});
  c.push_back({"vel_err_mps", "m/s", "horizontal velocity error, norm of (north, east)"});
  for (const auto& k : kState)
    c.push_back({std::string("sigma_") + k.quantity + "_" + tail(k), k.unit,
                 std::string("the estimator's own 1 sigma (square root of its covariance's diagonal), ") + k.text + in_F});
  c.push_back({"nees", "", "normalized estimation error squared (4 dof)"});
  c.push_back({"updated", "", "1 if a bearing was used at this frame, else 0"});
  c.push_back({"nis", "", "normalized innovation squared of the bearing (1 dof); 0 when not updated"});
  return c;
}

std::string uav_realization_rows(const UavStatsSetup& sc, long realization, const TmaRealization& r) {
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
