// Closure: does the diagnosis re-find the effects a simulation of the extended scene injects?
// Each of `runs` simulations of the scene with `errors` (realizations 0 .. runs - 1) is
// diagnosed as a recording (rnav_diagnose multi's diagnosis, these options); per injected
// effect: how often it is named with its scope, and the mean, spread and standard error of the
// named estimates against the injected values.
#pragma once

#include "estimators/diagnosis/multi_diagnose.hpp"
#include "sim/scene/recorded_scene.hpp"
#include "sim/scene/scene_errors.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace rnav {

struct ClosureRow {
  scene::InjectedEffect injected;
  std::vector<std::string> params;  ///< its parameter names as the diagnosis names them (from a run that named it)
  int runs = 0, named = 0;
  std::vector<double> mean, sd;     ///< per parameter, over the runs that named it
  /// per parameter: |mean - injected| <= 2 sd / sqrt(named) (the mean within two standard errors)
  std::vector<char> within_2se;
};

std::vector<ClosureRow> scene_closure(const MultiSensorData& real, const scene::RecordedScene& scene, const scene::SceneErrors& errors,
                                      const MultiDiagnoseOptions& o, int runs, std::uint64_t seed);

nlohmann::ordered_json closure_json(const std::vector<ClosureRow>& rows);

}  // namespace rnav
