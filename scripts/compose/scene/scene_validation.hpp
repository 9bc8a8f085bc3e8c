// What a simulation of a recorded scene gets wrong, measured: the recording's residual
// statistics per sensor:target pair placed among those of N simulations of its scene.
// Per pair, through the diagnosis's own association (the same options for the recording and
// every simulation):
//   mean, sd       of its residuals (measured minus the reference's prediction) per quantity
//                  (bearing [rad], range [m]); sd with n - 1;
//   lag1           their lag-1 autocorrelation in time order, sum (x_i - m)(x_(i+1) - m) /
//                  sum (x_i - m)^2;
//   detection_rate its associated detections over the sensor's scans.
// The band of a statistic is the 5 % and 95 % quantiles (linear between order statistics) of its
// finite values over the simulations; the real value is inside when it lies within it; rank =
// the fraction of simulations below it (ties half). With fewer than half the simulations giving
// the statistic (a pair they rarely detect) the band is undefined and the value not inside.
#pragma once

#include "estimators/diagnosis/multi_association.hpp"
#include "estimators/diagnosis/multi_sensor_data.hpp"
#include "sim/scene/recorded_scene.hpp"
#include "sim/scene/scene_errors.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav {

struct PairQuantityStats {
  int n = 0;
  double mean = NAN, sd = NAN, lag1 = NAN;
};

/// Mean, sd (n - 1) and lag-1 autocorrelation of residuals x in time order (sd and lag1 need 3).
PairQuantityStats residual_stats(const std::vector<double>& x);

/// One recording's (or simulation's) statistics.
struct SceneStats {
  std::map<std::string, PairQuantityStats> residuals;  ///< per "sensor:target:bearing" / ":range"
  std::map<std::string, double> detection_rate;        ///< per "sensor:target": associated / scans
  std::map<std::string, int> associated;               ///< per "sensor:target"
};

/// The statistics of recording d under association options o.
SceneStats scene_stats(const MultiSensorData& d, const AssociationOptions& o);

/// One row of the validation: a statistic of a pair's quantity under one model.
struct ValidationRow {
  std::string recording, pair, quantity, statistic, model;  ///< quantity: bearing, range (a landing radar: range, azimuth, elevation) or detection
  int n = 0;            ///< the recording's associated detections of the pair
  double real = NAN, band_lo = NAN, band_hi = NAN, rank = NAN;
  bool inside = false;
};

/// The rows of one model: every pair of the recording (`real`) against the simulations.
std::vector<ValidationRow> validation_rows(const std::string& recording, const std::string& model, const SceneStats& real,
                                           const std::vector<SceneStats>& sims);

/// The statistics of `runs` simulations (realizations 0 .. runs - 1 of seed) of the scene with
/// `errors`, each associated as the recording (`real` gives observer and truth), on `threads`
/// threads; the same for any thread count.
std::vector<SceneStats> simulated_stats(const MultiSensorData& real, const scene::RecordedScene& scene, const scene::SceneErrors& errors,
                                        const AssociationOptions& o, int runs, std::uint64_t seed, int threads);

/// Rows as JSON: {recording, pair, quantity, statistic, model, n, real, band_lo, band_hi, rank, inside}.
nlohmann::ordered_json rows_json(const std::vector<ValidationRow>& rows);

}  // namespace rnav
