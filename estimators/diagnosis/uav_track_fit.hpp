// The object's track estimated from azimuth-only data alone (no truth): a constant-velocity
// (CV) track fitted to the bearings by maximum likelihood (Gauss-Newton), with the detection of
// each frame associated to the track. This is the nominal model of the azimuth-only diagnosis
// without truth: the residual of a bearing is measured minus the fitted track's bearing, and the
// track's Jacobian enters every effect test as a nuisance (an effect is only what the track
// cannot absorb).
//
// Frame F: local level at the first observer sample, x north, z east; 2-D vectors (north,
// east). Track: p(t) = p0 + v (t - t_ref). Bearing from observer o: beta = atan2(e_p - e_o,
// n_p - n_o), clockwise from north.
//
// Initialisation (robust to clutter, deterministic): RANSAC over minimal sets of 4 frames (one
// detection each), each solved by the pseudo-linear estimator
//   (p_n - o_n) sin(beta) - (p_e - o_e) cos(beta) = 0   (linear in p0, v),
// scored by the number of frames with a detection within the gate; then alternating
// association (nearest detection within the gate) and Gauss-Newton until the association is
// stable.
#pragma once

#include "estimators/diagnosis/azimuth_data.hpp"
#include "estimators/diagnosis/plane_series.hpp"

#include <Eigen/Dense>

#include <cstdint>
#include <vector>

namespace rnav {

struct TrackFitOptions {
  double gate_deg = 4;        ///< [deg] association gate around the track's bearing, (0, 90]
  int ransac_trials = 400;    ///< minimal-set trials of the initialisation, >= 1
  std::uint64_t seed = 1;     ///< random seed of the initialisation (deterministic)
  int max_iterations = 30;    ///< Gauss-Newton iterations per association round
};

/// One frame of observation for the fit.
struct TrackObs {
  double t_s = 0;
  Eigen::Vector2d o_F;    ///< [m] observer (north, east) in F, from its navigation solution
  Eigen::Vector2d vo_F;   ///< [m/s] observer velocity (central difference of its positions)
  std::vector<double> bearings_rad;  ///< the frame's detections
};

/// A CV track: p(t) = p0 + v (t - t_ref).
struct CvTrack {
  Eigen::Vector2d p0_F = Eigen::Vector2d::Zero();  ///< [m] position at t_ref (north, east)
  Eigen::Vector2d v_F = Eigen::Vector2d::Zero();   ///< [m/s] velocity
  double t_ref_s = 0;
  Eigen::Vector2d at(double t_s) const { return p0_F + v_F * (t_s - t_ref_s); }
  /// Bearing [rad] from observer o at t.
  double bearing(const TrackObs& x) const;
  /// d bearing / d (p0_n, p0_e, v_n, v_e): [-de/r^2, dn/r^2, dt (-de/r^2), dt dn/r^2].
  Eigen::Vector4d jacobian(const TrackObs& x) const;
  /// [rad/s] bearing rate: (d x dv)/r^2 with d = p - o, dv = v - v_o (2-D cross product n,e).
  double bearing_rate(const TrackObs& x) const;
};

struct TrackFit {
  CvTrack track;
  Eigen::Matrix4d cov;                 ///< [m, m/s] of (p0_n, p0_e, v_n, v_e), scaled by the residual variance
  std::vector<int> associated;         ///< per frame: index of the associated detection, -1 none
  double rms_rad = 0;                  ///< residual RMS over associated frames
  int n_associated = 0;
  double condition = 0;                ///< condition number of the (equilibrated) normal matrix
};

/// Observations of `data` in F (observer interpolated at each frame; frames outside the
/// observer's time span or in gaps > 2 s are dropped).
std::vector<TrackObs> track_observations(const AzimuthData& data, const LocalLevelFrame& F);

/// Fit a CV track to the frames with t in [t_begin, t_end]. Throws ConfigError when the track is
/// not observable from this observer path (normal matrix singular) or when fewer than 10
/// frames associate.
TrackFit fit_cv_track(const std::vector<TrackObs>& obs, double t_begin, double t_end, const TrackFitOptions& o);

}  // namespace rnav
