// Diagnosis of a landing-radar flight test against the nominal (paper's) model.
//
// Residuals: y = zeta_meas - zeta_nav per channel (range m, course rad, glide rad), with the
// nav solution interpolated to each plot's time and converted into the radar's polar basis.
// Nominal model: y = b_channel + white noise (the paper's constant bias; sigma per channel
// estimated from the data by the fit). Candidate effects are regressors (the catalogue below);
// forward selection adds the effect with the largest likelihood ratio while its p-value,
// Bonferroni-corrected over the catalogue (and over the scan grid of scanned effects), stays
// below alpha: the familywise false-alarm rate on nominal data is at most alpha. Then noise
// tests (noise_scale, outliers, correlated_noise), confounding between effects in this geometry
// (canonical correlation of their regressors), an out-of-sample gain (fit before split_time_s,
// score after it), and what stays unexplained.
//
// Catalogue (estimate units): range_gain [1]: dD = g D; time_offset [s]: dzeta = -zeta_dot tau;
// elevation_refraction [rad]: dEg = k cot Eg; azimuth_elevation_coupling [rad]: dEk = c tan Eg;
// site_offset [m] (east, north, up: surveyed minus true): dzeta = J delta; bias_drift
// (range m/s, course rad/s, glide rad/s): dzeta = r t; bias_step (m, rad, rad, at a scanned
// time); periodic (amplitudes, at a scanned period); noise_scale [1]; outliers [fraction];
// correlated_noise [s]. Nominal: range_bias [m], azimuth_bias [rad], elevation_bias [rad].
#pragma once

#include "prl_flight_data.hpp"
#include "stats.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace rnav {

struct DiagnoseOptions {
  double split_time_s = 400;   ///< [s] estimation window before, scored window after (paper's switch)
  double alpha = 0.01;         ///< familywise false-alarm level of the effect search
  double sigma_range_m = 12;   ///< [m] nominal radar noise, 1 sigma (Table 1: 24 m at 2 sigma), for noise_scale
  double sigma_course_deg = 0.25;  ///< [deg] idem
  double sigma_glide_deg = 0.3;    ///< [deg] idem
  double outlier_z = 5;        ///< robust z beyond which a residual is an outlier
  double confound_corr = 0.9;  ///< canonical correlation above which two effects are confounded
  double max_nav_gap_s = 2.0;  ///< [s] plots in longer nav gaps are not used
  /// The nav solution's time-correlated position error per axis (a Gauss-Markov process; the
  /// simulator's default 1.9 m / 120 s): it enters the residuals projected onto each channel
  /// (range 1, course 1/horizontal range, glide 1/D) and the fits are generalised least
  /// squares with that covariance. 0 treats the nav solution as exact.
  double nav_sigma_m = 1.9;
  double nav_tau_s = 120;      ///< [s] its correlation time
};

struct EffectResult {
  std::string name;
  std::vector<double> estimate, stderr_;  ///< one per parameter (see the catalogue's units)
  std::vector<std::string> params;        ///< parameter names
  double evidence_lr = 0;                  ///< 2 log likelihood ratio against the model without it
  double p_value = 1;                      ///< its p-value (Bonferroni-corrected for scans)
  double delta_bic = 0;                    ///< BIC(without) - BIC(with): > 10 is very strong
  std::vector<std::string> confounded_with;
  std::string note;
  bool nominal = false;
};

struct ChannelGain {
  int n = 0;
  double nominal_rms = 0, extended_rms = 0;        ///< [m or rad] residual RMS after each model
  double nominal_loglik = 0, extended_loglik = 0;  ///< out-of-sample Gaussian log-likelihood
};

struct DiagnoseReport {
  std::string kind = "prl";  ///< "prl" (landing radar) or "uav" (azimuth-only)
  std::string reference;     ///< uav: what the residuals are taken against (truth or fitted track)
  std::vector<EffectResult> effects;
  std::map<std::string, ChannelGain> gain;  ///< "range", "course", "glide", and "truth_position_m" if truth
  std::vector<std::string> unexplained;
  /// Per non-scanned catalogue effect and parameter: the smallest value this data would detect,
  /// z * SE with z the two-sided normal quantile at alpha / (catalogue size).
  std::map<std::string, std::map<std::string, double>> detection_limits;
  int plots_used = 0, plots_dropped = 0;
  double split_time_s = 0;
  /// Per plot: time, residual (meas - nav) and the nominal and extended models' fits (full data).
  /// uav: y = (bearing residual [rad], bearing rate [rad/s], range [m]); fits in channel 0.
  struct Row {
    double t_s;
    std::array<double, 3> y, nominal, extended;
    bool outlier;
  };
  std::vector<Row> rows;
  /// Write rows as CSV. prl: t_s, then per channel residual, nominal, extended; outlier flag.
  /// uav: t_s,bearing_residual_rad,bearing_extended_rad,bearing_rate_radps,range_m,outlier.
  void write_residuals_csv(const std::string& file) const;
  nlohmann::ordered_json to_json() const;
  std::string text() const;
};

DiagnoseReport diagnose_prl(const PrlFlightData& data, const DiagnoseOptions& o);


}  // namespace rnav
