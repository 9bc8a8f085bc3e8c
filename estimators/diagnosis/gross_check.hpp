// Gross checks of a landing flight's radar plots against the geometry of its nav solution,
// before any diagnosis: a unit mixed up (ranges in kilometres, angles in radians, nav heights in
// feet, an azimuth reference in radians) passes every range check and used to come out as a
// confident, wrong "effect" (a range gain of -0.999, an azimuth bias of -113.8 deg). Here a
// mismatch far beyond any catalogue effect is an error that names the column and the likely unit.
//
// With D, Ek, Eg the measured range, course (azimuth from the reference) and glide (elevation)
// and D^, Ek^, Eg^ those computed from the nav positions:
//   range:  q = median(D / D^); an error unless 1 / kMaxRangeScale <= q <= kMaxRangeScale;
//   course: d = median(wrap(Ek - Ek^)); an error if |d| > kMaxAngleOffsetDeg; and the slope b of
//           the least-squares line Ek = a + b Ek^ (where Ek^ spreads over kMinSpreadDeg or more):
//           an error unless 1 / kMaxSlope <= b <= kMaxSlope;
//   height: the least-squares line H = c + d h of the aircraft's height from the radar,
//           H = D sin Eg + h_R + (D cos Eg)^2 / (2 R_E), on its height h in nav.csv: nav
//           heights in a length unit of factor f make d = f; the site's height h_R in that
//           unit makes d = 1 and offsets every H by c (beyond kMinSiteHeightOffsetM, and h_R
//           over the site height nav implies, h_R - c, near 1 / f: site.json radar.h_m). Where
//           H spreads less than kMinHeightSpreadM, nav's unit from the median ratio h / H over
//           plots with H >= kMinHeightM;
//   glide:  the same as the course.
// The likely unit: the factor f among kilometres (1000), feet (0.3048), nautical miles (1852),
// statute miles (1609.344), millimetres (0.001) [range] or radians and milliradians in a degree
// column (180/pi and its inverse, 1000 pi/180) [angles] with |q f - 1| (or |b f - 1|) <= kUnitMatch; an azimuth_reference_deg r read
// as radians (r <= 2 pi, |d| > kMinRefOffsetDeg and d = r (1 - 180/pi) wrapped within
// kRefMatchDeg: checked before the offset, which wrapping may bring under its bound); for a
// height ratio near a length unit's factor, nav heights in that unit.
#pragma once

#include "common/physics/frames.hpp"

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace rnav {

struct PlotGeometry {
  double range_m, course_rad, glide_rad;                 ///< measured
  double range_pred_m, course_pred_rad, glide_pred_rad;  ///< from the nav solution
  double nav_h_m;                                        ///< the nav solution's height, as read [m]
};

constexpr double kMaxRangeScale = 1.25;     ///< a range 25 % off is no radar effect (range_gain is a few 1e-3)
constexpr double kSiteOffM = 10000;         ///< [m] median ranges this far apart: the radar site is another place's
constexpr double kMaxAngleOffsetDeg = 20;   ///< [deg] a bias of 20 deg is no radar effect
constexpr double kMaxSlope = 2;             ///< an angle scaled by 2 or 1/2
constexpr double kMinSpreadDeg = 0.5;       ///< [deg] the computed angle's spread (sd) a slope needs
constexpr double kUnitMatch = 0.03;         ///< |q f - 1| within which a unit's factor f is named
constexpr double kAngleUnitMatch = 0.1;     ///< the same for an angle's slope (its noise and nav error bend it)
constexpr double kMinHeightM = 50;          ///< [m] heights compared only above this (a ratio needs a height)
constexpr std::size_t kMinHeightPlots = 30; ///< plots the height ratio needs
constexpr double kEarthRadiusM = 6371000;   ///< [m] mean Earth radius: the drop d^2 / (2 R) over d
constexpr double kHeightUnitMatch = 0.1;     ///< kUnitMatch for heights (an elevation bias tilts them)
constexpr double kMinHeightSpreadM = 30;      ///< [m] heights spread (sd) enough to tell a ratio from an offset
constexpr double kMinSiteHeightOffsetM = 100;  ///< [m] a site height's unit named only beyond this offset
constexpr double kRefMatchDeg = 5;          ///< [deg] a radians reference's offset matched within
constexpr double kMinRefOffsetDeg = 2;      ///< [deg] ... and beyond (a real azimuth bias is well below)

/// The length unit whose factor f brings a ratio q (measured / expected) to 1, |q f - 1| <=
/// tol: "kilometres", "feet", "nautical miles", "statute miles", "millimetres"; else "".
std::string range_unit_of(double q, double tol = kUnitMatch);

/// [rad] 2 pi read as degrees: a bearing column holding radians stays within +- this.
constexpr double kRadiansAsDegreesRad = 2 * M_PI * M_PI / 180;
constexpr int kMinUnitSamples = 10;  ///< bearings a radians check needs

/// Whether a sensor's bearings hold radians in a degree column: all n of them (at least
/// kMinUnitSamples) within +-kRadiansAsDegreesRad while most of the `refs` reference bearings
/// (`refs_outside` of them outside [-1 deg, kRadiansAsDegreesRad + 1 deg]) are not.
bool bearings_look_like_radians(int n, int inside, int refs, int refs_outside);
/// Whether reference bearing b [rad] lies outside the band radians-as-degrees bearings fill.
bool outside_radians_band(double b_rad);

/// Throws ConfigError naming the file's column and the likely unit (files: radar.csv, nav.csv,
/// site.json as read by PrlFlightData::read_folder). azimuth_reference_deg: site.json's value;
/// radar_h_m: the radar site's ellipsoidal height [m].
void check_plot_units(const std::vector<PlotGeometry>& plots, double azimuth_reference_deg, double radar_h_m);

/// truth.csv's heights against nav.csv's (both the aircraft's): the median ratio of each truth
/// height to nav's interpolated at its time, over samples where nav's is kMinHeightM or more (at
/// least kMinHeightPlots of them); outside [1 / kMaxRangeScale, kMaxRangeScale] an error naming
/// truth.csv h_m and the likely unit. Both in time order.
void check_truth_heights(const std::vector<GeoSample>& nav, const std::vector<GeoSample>& truth);

}  // namespace rnav
