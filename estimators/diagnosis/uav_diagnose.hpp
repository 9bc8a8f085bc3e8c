// Diagnosis of azimuth-only data (azimuth_data.hpp) against the nominal model: bearing = true
// bearing + white noise (zero mean, sigma_deg), object at constant velocity. An adapter that
// states the problem for the effect-search engine (../model_id/effect_search.hpp).
//
// Two reference tracks for the residual r = measured - reference bearing (one channel,
// "bearing" [rad]):
//  - truth (truth.csv present, ignore_truth false): the reference is the object's GNSS track;
//    each frame's detection nearest to the true bearing is the object's (within gate_deg; one
//    within 3 gates is kept as a gross error for the outlier test, beyond that the frame shows
//    only clutter and is dropped). The
//    reference track itself is then checked against the target model (target_model.hpp): a
//    turn or speed change is named target_maneuver.
//  - estimated (no truth, or ignore_truth): the reference is a constant-velocity track fitted to
//    the bearings themselves (uav_track_fit.hpp); its Jacobian (position and velocity) is the
//    nuisance of every fit, so an effect is only what a CV track cannot absorb, and
//    target_maneuver (a velocity change at a scanned time) joins the catalogue. The truth, when
//    present, only scores the gain.
// Catalogue: bearing_bias [rad]: 1; time_offset [s] (stamp minus true time): -beta_dot;
// bias_drift [rad/s]: t - t0; periodic (sin/cos, period scanned 4 s to span / 3);
// target_maneuver (time scanned, dv north/east [m/s]): d beta / d p (t - t_m)+.
// Gain: the named effects fitted on the first split_fraction of the span, scored on the rest
// (bearing RMS and predictive log-likelihood); without truth as reference but with truth
// present, the extrapolated track's position error against truth ("truth_position_m").
#pragma once

#include "estimators/diagnosis/azimuth_data.hpp"
#include "estimators/diagnosis/diagnose_report.hpp"

#include <cstdint>

namespace rnav {

struct UavDiagnoseOptions {
  double gate_deg = 4;          ///< [deg] association gate around the reference bearing, (0, 90]
  double sigma_deg = 0.5;       ///< [deg] nominal bearing noise, 1 sigma, > 0
  double split_fraction = 0.6;  ///< the first fraction of the time span is the estimation window, (0.2, 0.9)
  SearchOptions search;         ///< alpha (familywise, default 0.01), power, confound_corr, ...
  bool ignore_truth = false;    ///< diagnose on an estimated track even when truth.csv is present
  bool test_target_model = true;  ///< with truth as reference: check it against the target model
  /// with truth as reference: refuse references that do not fit the bearings (shifted in time,
  /// another place's, reciprocal, mirrored or frozen bearings; bearing_reference_check.hpp)
  bool check_references = true;
  int maneuver_grid = 39;       ///< scan grid of target_maneuver (evenly inside the span), >= 2
  std::uint64_t seed = 1;       ///< seed of the track fit's initialisation (deterministic)
};

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o);

}  // namespace rnav
