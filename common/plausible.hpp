// One validation layer for measured and logged data, shared by the CSV readers and the LCM-log
// readers: every value is checked where it enters against the physical range of its quantity,
// and positions against each other (a swapped latitude/longitude header puts the aircraft
// thousands of kilometres from its radar). Each check throws ConfigError naming `where` (file and
// line, or log, channel and sample), the quantity and the value.
#pragma once

#include "frames.hpp"

#include <string>

namespace rnav::plausible {

/// [s] |t| at most this: Unix seconds until the year 2286, or any relative time scale.
inline constexpr double kMaxAbsTimeS = 1e10;
/// [m] Heights of the ellipsoid: from the Dead Sea shore minus margin to a high-altitude UAV.
inline constexpr double kMinHeightM = -1000, kMaxHeightM = 1e5;
/// [m] Ranges of the sensors modelled (landing radar, marine radar, lidar): positive, below
/// 1000 km.
inline constexpr double kMaxRangeM = 1e6;
/// [rad] Angles (azimuth, elevation, bearing) before wrapping: |x| at most two turns.
inline constexpr double kMaxAbsAngleRad = 4 * 3.14159265358979323846;
/// [m] Two positions of one scene (a radar and its aircraft, an observer and its boat) at most
/// this far apart along the surface: a landing approach starts within 100 km, a sensor sees
/// within a few tens; 2000 km leaves room and still catches swapped coordinates.
inline constexpr double kMaxSceneDistanceM = 2e6;

void time(const std::string& where, double t_s);
void geodetic(const std::string& where, const Geodetic& g, bool check_height = true);
void range(const std::string& where, double range_m);
/// Strict time order of a sampled stream: t_s after prev_t_s (a corrupt time stamp, or samples
/// out of order, would otherwise be sorted away or interpolated across silently).
void after(const std::string& where, double t_s, double prev_t_s);
void angle(const std::string& where, const std::string& name, double rad);
/// `g` within kMaxSceneDistanceM of `centre` (the site or first observer position), by the
/// haversine distance on a sphere of the WGS84 equatorial radius (enough for a bound).
void near(const std::string& where, const Geodetic& g, const Geodetic& centre, const std::string& centre_name);

}  // namespace rnav::plausible
