// A landing-radar diagnosis report (rnav_diagnose prl --json) as the landing radar's errors in
// a simulation (the scenario's prl_effects): the report's named effects through the same
// columns the diagnosis fits (common/physics/prl_effect_columns.hpp). Each entry maps to its keys:
//   range_gain                  g            -> range_gain
//   time_offset                 tau_s        -> time_offset_s
//   elevation_refraction        k_rad        -> elevation_refraction_rad
//   azimuth_elevation_coupling  c_rad        -> azimuth_elevation_coupling_rad
//   site_offset                 east/north/up_m -> site_offset_*_m
//   bias_drift                  range_mps, course_radps, glide_radps -> drift_* (the simulation's
//                               drift starts at sim time 0, the diagnosis's at the flight's first
//                               plot: they differ by a constant, the nominal model's bias)
//   bias_step                   range_m, course_rad, glide_rad at t_s -> step_time_s, step_*
//                               (one step time for all channels)
//   periodic                    sin_*, cos_* at period_s -> periodic_period_s, periodic_* (the
//                               simulation's oscillation has phase 0: cos must be 0 within 2 SE)
//   noise_scale, outliers,      the simulation's fluctuation noise is one model for all three
//   correlated_noise            channels: each finding must be named on all three with values
//                               within 3 SE of their mean, which is taken (correlated_noise: its
//                               correlation time, a share above 0.95)
// An effect the simulation cannot make is a ConfigError naming it and why, never dropped.
#pragma once

#include "sim/prl/prl_options.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace rnav {

/// The effects of report `j` (read from `source`, named in errors) as prl_effects.
PrlEffectsOptions prl_effects_from_report(const nlohmann::json& j, const std::string& source);

}  // namespace rnav
