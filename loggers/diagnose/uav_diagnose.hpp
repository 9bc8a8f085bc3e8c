// Diagnosis of azimuth-only data against the nominal model (bearing = true bearing + white
// noise, zero mean), when the object's truth is known (truth.csv): each frame's detection
// nearest to the true bearing within gate_deg is the object's (the others are clutter); the
// residual r = measured - true bearing is regressed on the catalogue: bearing_bias (rad),
// bearing_time_offset (s, sensor stamp minus true time: dr = -beta_dot tau), bias_drift
// (rad/s), periodic; noise_scale, outliers, correlated_noise are tested on the residuals. The
// same decision rule as the landing-radar diagnosis (familywise alpha, Bonferroni). The gain:
// fit before split, score after, as bearing RMS against the GNSS truth.
// Without truth the object's track must be estimated first: not implemented yet.
#pragma once

#include "azimuth_data.hpp"
#include "prl_diagnose.hpp"

namespace rnav {

struct UavDiagnoseOptions {
  double gate_deg = 4;         ///< [deg] association gate around the true bearing
  double sigma_deg = 0.5;      ///< [deg] nominal bearing noise, 1 sigma (for noise_scale)
  double alpha = 0.01;         ///< familywise false-alarm level
  double split_fraction = 0.6; ///< the first fraction of the time span is the estimation window
  double outlier_z = 5;        ///< robust z beyond which a residual is an outlier
  double confound_corr = 0.9;  ///< correlation above which two effects are confounded
};

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o);

}  // namespace rnav
