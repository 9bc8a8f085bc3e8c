// Diagnosis of a landing-radar flight test (prl_flight_data.hpp) against the nominal (paper's)
// model: an adapter that states the problem for the effect-search engine
// (../model_id/effect_search.hpp) and turns its result into a DiagnoseReport.
//
// Residuals: y = zeta_meas - zeta_nav per channel (range [m], course [rad], glide [rad]), with
// the nav solution interpolated to each plot's time and converted into the radar's polar basis.
// Nominal model: y = b_channel + noise (the paper's constant bias per channel: the nuisance).
// The noise is identified per channel by the engine (white, Gauss-Markov, their sum, outlier
// flags); the nav solution's own slowly correlated error enters it there.
//
// Catalogue (estimate units; zeta = (D, Ek, Eg), J = d zeta / d p, zeta_dot = J v_nav):
//   range_gain [1]:                  dD = g D
//   time_offset [s]:                 dzeta = -zeta_dot tau   (radar stamp minus true time)
//   elevation_refraction [rad]:      dEg = k cot Eg
//   azimuth_elevation_coupling [rad]: dEk = c tan Eg
//   site_offset [m] (east, north, up of the surveyed site minus the true one): dzeta = J R delta
//   bias_drift per channel [m/s, rad/s]: dzeta_c = r (t - t0)
//   bias_step per channel [m, rad]: a jump at a scanned time (10 % to 90 % of the span)
//   periodic per channel: sin/cos at a scanned period (4 s to span / 3, ratio 1.05)
// Nominal parameters reported: range_bias [m], azimuth_bias [rad], elevation_bias [rad].
// Gain: fit on t < split_time_s, score the rest, per channel and (with truth.csv) as the
// compensated plot's position error against truth ("truth_position_m").
#pragma once

#include "estimators/diagnosis/diagnose_report.hpp"
#include "estimators/diagnosis/prl_flight_data.hpp"

namespace rnav {

struct DiagnoseOptions {
  double split_time_s = 400;       ///< [s] estimation window before, scored window after (paper's switch)
  /// alpha (familywise, default 0.01), power, confound_corr, ...; holdout_min_z defaults to 1
  /// here (the radar's effects are constants of the installation whose signature grows towards
  /// the threshold, e.g. a site offset ~ 1/D: a 1-SE estimate from the far window is the honest
  /// extrapolation), where the engine's default is 2.
  SearchOptions search = [] {
    SearchOptions s;
    s.holdout_min_z = 1;
    return s;
  }();
  double sigma_range_m = 12;       ///< [m] nominal radar noise, 1 sigma (Table 1: 24 m at 2 sigma), > 0
  double sigma_course_deg = 0.25;  ///< [deg] idem, > 0
  double sigma_glide_deg = 0.3;    ///< [deg] idem, > 0
  double max_nav_gap_s = 2.0;      ///< [s] plots in longer nav gaps are not used, > 0
  /// [s] the nav velocity behind the measurement rates (time_offset's columns) is the slope of a
  /// line fitted to the nav positions within this window centred on the plot (at least three
  /// samples; else the segment's difference), >= 0 (0: the segment's difference).
  double rate_window_s = 2.0;
  int step_grid = 33;              ///< scan grid of bias_step (10 % to 90 % of the span), >= 2
  /// The nav solution's time-correlated position error per axis (Gauss-Markov; the simulator's
  /// default 1.9 m / 120 s). It is part of the nominal model: projected onto each channel
  /// (range 1, course 1 / horizontal range, glide 1 / D; RMS over the plots) it is the nominal
  /// correlated noise, so correlated_noise is named only where the data depart from it.
  /// 0 treats the nav solution as exact.
  double nav_sigma_m = 1.9;        ///< [m] >= 0
  double nav_tau_s = 120;          ///< [s] its correlation time, > 0
};

DiagnoseReport diagnose_prl(const PrlFlightData& data, const DiagnoseOptions& o);

}  // namespace rnav
