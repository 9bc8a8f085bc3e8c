// Diagnosis of azimuth-only data against the nominal model: bearing = true bearing + white
// noise (zero mean, sigma_deg), object moving at constant velocity.
//
// Two reference tracks for the residual r = measured - reference bearing:
//  - truth (truth.csv present, ignore_truth false): the reference is the object's GNSS track;
//    each frame's detection nearest to the true bearing within gate_deg is the object's.
//  - estimated (no truth, or ignore_truth): the reference is a constant-velocity track fitted to
//    the bearings themselves (uav_track_fit.hpp); its Jacobian (position and velocity) is a
//    nuisance in every fit, so an effect is only what a CV track cannot absorb; target_maneuver
//    (a velocity change at a scanned time) is then in the catalogue. The truth, when present, is
//    used only to score the gain.
// Catalogue: bearing_bias [rad]; bearing_time_offset [s] (stamp minus true time: dr =
// -beta_dot tau); bias_drift [rad/s]; periodic (period scanned); target_maneuver (time scanned;
// velocity change north/east [m/s]); noise_scale, outliers, correlated_noise from the residuals.
// Forward selection with the landing-radar diagnosis's rule (familywise alpha, Bonferroni over
// the catalogue and the scan grids); regression SEs inflated for AR(1) noise. The gain: fit on
// the first split_fraction of the span, score the rest: bearing residual RMS and Gaussian
// log-likelihood, and with truth the position error of the (extrapolated) track.
#pragma once

#include "azimuth_data.hpp"
#include "prl_diagnose.hpp"

namespace rnav {

struct UavDiagnoseOptions {
  double gate_deg = 4;         ///< [deg] association gate around the reference bearing, (0, 90]
  double sigma_deg = 0.5;      ///< [deg] nominal bearing noise, 1 sigma (for noise_scale), > 0
  double alpha = 0.01;         ///< familywise false-alarm level, (0, 0.5)
  double split_fraction = 0.6; ///< the first fraction of the time span is the estimation window, (0.2, 0.9)
  double outlier_z = 5;        ///< robust z beyond which a residual is an outlier, > 2
  double confound_corr = 0.9;  ///< correlation above which two effects are confounded, (0, 1)
  bool ignore_truth = false;   ///< diagnose on an estimated track even when truth.csv is present
  std::uint64_t seed = 1;      ///< seed of the track fit's initialisation (deterministic)
};

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o);

}  // namespace rnav
