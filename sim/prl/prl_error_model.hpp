// Landing-radar (PRL) error model: a list of effects, each adding to the systematic
// (slowly varying) and/or fluctuation (white) part of the polar measurement error:
//   zeta_meas = zeta_true + sum(systematic) + sum(fluctuation)              (docs/method.md eq. 1)
// Open for further effects: derive from PrlErrorEffect and add it in PrlErrorModel's constructor.
#pragma once

#include "common/physics/frames.hpp"
#include "common/physics/random.hpp"
#include "sim/prl/prl_options.hpp"

#include <memory>
#include <string>
#include <vector>

namespace rnav {

/// Error in the radar's polar basis.
struct PolarError {
  double range_m = 0, course_rad = 0, glide_rad = 0;
  PolarError& operator+=(const PolarError& o) {
    range_m += o.range_m;
    course_rad += o.course_rad;
    glide_rad += o.glide_rad;
    return *this;
  }
};

/// What an effect may depend on: the plot's time and the true geometry.
struct PlotTruth {
  double t_s = 0;             ///< [s] sim time of validity
  Polar polar;                ///< true (D, Ek, Eg) of the aircraft from the radar
  Eigen::Vector3d p_RA_R;     ///< [m] true position of aircraft A from radar R, frame R
  Eigen::Vector3d v_A_R;      ///< [m/s] true velocity, frame R
};

class PrlErrorEffect {
 public:
  virtual ~PrlErrorEffect() = default;
  virtual std::string name() const = 0;
  /// Start a realization (draw initial states).
  virtual void start(Rng&) {}
  /// Add this effect's contribution for one plot (plots in increasing time).
  virtual void apply(const PlotTruth& truth, Rng& rng, PolarError& systematic,
                     PolarError& fluctuation) = 0;
};

/// Constant systematic error (Table 1: 6 m, 0.1 deg, 0.15 deg).
class ConstantBias : public PrlErrorEffect {
 public:
  explicit ConstantBias(const PolarError& b) : b_(b) {}
  std::string name() const override { return "constant_bias"; }
  void apply(const PlotTruth&, Rng&, PolarError& sys, PolarError&) override { sys += b_; }

 private:
  PolarError b_;
};

/// One Gauss-Markov process per coordinate (sigma per coordinate [m, rad, rad], correlation
/// time tau [s], stationary start), added to the systematic part (Part::kSystematic:
/// gauss_markov_drift, a slowly varying systematic error) or to the fluctuation
/// (Part::kFluctuation: correlated_noise, an AR(1) fluctuation): one process, two roles.
class PolarGaussMarkov : public PrlErrorEffect {
 public:
  enum class Part { kSystematic, kFluctuation };
  PolarGaussMarkov(const PolarError& sigma, double tau_s, Part part);
  std::string name() const override { return part_ == Part::kSystematic ? "gauss_markov_drift" : "correlated_noise"; }
  void start(Rng& rng) override;
  void apply(const PlotTruth& truth, Rng& rng, PolarError& sys, PolarError& fl) override;

 private:
  GaussMarkov d_, e_, g_;
  Part part_;
  double last_t_s_ = 0;
};

/// White fluctuation error, 1 sigma per coordinate (Table 1 gives 2 sigma).
class WhiteFluctuation : public PrlErrorEffect {
 public:
  explicit WhiteFluctuation(const PolarError& sigma) : s_(sigma) {}
  std::string name() const override { return "white_fluctuation"; }
  void apply(const PlotTruth&, Rng& rng, PolarError&, PolarError& fl) override;

 private:
  PolarError s_;
};

/// Occasional gross errors (outliers): with probability p a plot gets scale * sigma more noise.
class Outliers : public PrlErrorEffect {
 public:
  Outliers(double p, const PolarError& sigma) : p_(p), s_(sigma) {}
  std::string name() const override { return "outliers"; }
  void apply(const PlotTruth&, Rng& rng, PolarError&, PolarError& fl) override;

 private:
  double p_;
  PolarError s_;
};

/// Deterministic systematic effects of the diagnosis catalogue (see PrlEffectsOptions):
/// range_gain, time_offset, elevation_refraction, azimuth_elevation_coupling, site_offset,
/// bias_drift, bias_step, periodic: C(plot) theta with the columns the diagnosis fits
/// (common/physics/prl_effect_columns.hpp, where each term's equation is written).
class GeometricEffects : public PrlErrorEffect {
 public:
  GeometricEffects(const PrlEffectsOptions& fx, double azimuth_reference_deg);
  std::string name() const override { return "catalogue_systematic"; }
  void apply(const PlotTruth& truth, Rng&, PolarError& sys, PolarError&) override;

 private:
  PrlEffectsOptions fx_;
  Eigen::Matrix3d R_R_ENU_;  // (east, north, up) -> radar frame R (prl_effect::R_R_ENU)
};

class PrlErrorModel {
 public:
  /// @param fx  further effects (default: none)
  /// @param azimuth_reference_deg  the radar frame's x bearing (to rotate a site offset into R)
  explicit PrlErrorModel(const PrlOptions& o, const PrlEffectsOptions& fx = {},
                         double azimuth_reference_deg = 0);
  void start(Rng& rng);
  /// Errors of one plot: systematic part and total (systematic + fluctuation).
  void apply(const PlotTruth& truth, Rng& rng, PolarError& systematic, PolarError& total);
  const std::vector<std::unique_ptr<PrlErrorEffect>>& effects() const { return effects_; }

 private:
  std::vector<std::unique_ptr<PrlErrorEffect>> effects_;
};

}  // namespace rnav
