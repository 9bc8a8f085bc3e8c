#include "scripts/compose/scene/scene_closure.hpp"

#include "scripts/compose/scene/scene_from_recording.hpp"
#include "sim/scene/scene_sim.hpp"

#include <cmath>

namespace rnav {

std::vector<ClosureRow> scene_closure(const MultiSensorData& real, const scene::RecordedScene& scene, const scene::SceneErrors& errors,
                                      const MultiDiagnoseOptions& o, int runs, std::uint64_t seed) {
  std::vector<ClosureRow> rows;
  for (const auto& e : errors.effects) {
    ClosureRow r;
    r.injected = e;
    r.runs = runs;
    rows.push_back(r);
  }
  std::vector<std::vector<std::vector<double>>> est(rows.size());  // per effect, per run named: its estimate
  for (int k = 0; k < runs; ++k) {
    const MultiReport rep = diagnose_multi(recording_of(real, scene::simulate(scene, errors, seed, static_cast<std::uint64_t>(k))), o);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& inj = rows[i].injected;
      for (const auto& f : rep.result.effects)
        if (f.name == inj.name && f.scope.sensor == inj.sensor && f.scope.target == inj.target && f.estimate.size() == inj.theta.size()) {
          ++rows[i].named;
          rows[i].params = f.params;
          est[i].push_back(f.estimate);
          break;
        }
    }
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ClosureRow& r = rows[i];
    const std::size_t P = r.injected.theta.size();
    r.mean.assign(P, NAN), r.sd.assign(P, NAN), r.within_2se.assign(P, 0);
    if (est[i].empty()) continue;
    for (std::size_t p = 0; p < P; ++p) {
      double m = 0, s = 0;
      for (const auto& x : est[i]) m += x[p];
      m /= static_cast<double>(est[i].size());
      for (const auto& x : est[i]) s += (x[p] - m) * (x[p] - m);
      r.mean[p] = m;
      r.sd[p] = est[i].size() > 1 ? std::sqrt(s / static_cast<double>(est[i].size() - 1)) : NAN;
      const double se = r.sd[p] / std::sqrt(static_cast<double>(est[i].size()));
      r.within_2se[p] = std::isfinite(se) && std::abs(m - r.injected.theta[p]) <= 2 * se;
    }
  }
  return rows;
}

nlohmann::ordered_json closure_json(const std::vector<ClosureRow>& rows) {
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(); };
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const auto& r : rows) {
    nlohmann::ordered_json x{{"name", r.injected.name}, {"sensor", r.injected.sensor}, {"target", r.injected.target}, {"params", r.params},
                             {"injected", r.injected.theta}, {"runs", r.runs}, {"named", r.named}};
    x["mean"] = nlohmann::ordered_json::array();
    x["sd"] = nlohmann::ordered_json::array();
    x["within_2se"] = nlohmann::ordered_json::array();
    for (std::size_t p = 0; p < r.injected.theta.size(); ++p) {
      x["mean"].push_back(num(r.mean[p]));
      x["sd"].push_back(num(r.sd[p]));
      x["within_2se"].push_back(static_cast<bool>(r.within_2se[p]));
    }
    j.push_back(x);
  }
  return j;
}

}  // namespace rnav
