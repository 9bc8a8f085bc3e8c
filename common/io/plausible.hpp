// One validation layer for measured and logged data, shared by the CSV readers and the LCM-log
// readers: every value is checked where it enters against the physical range of its quantity,
// and positions against each other (a swapped latitude/longitude header puts the aircraft
// thousands of kilometres from its radar). Each check throws ConfigError naming `where` (file and
// line, or log, channel and sample), the quantity and the value.
#pragma once

#include "common/physics/frames.hpp"

#include <string>
#include <vector>

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

/// Positions of one file or JSON object, with the names of its latitude and longitude columns
/// as a message should give them ("nav.csv lat_deg", "site.json radar.lat_deg").
struct NamedPositions {
  std::string lat_name, lon_name;
  std::vector<Geodetic> g;
};
/// The positions of a track, without their times (for coordinates_in_degrees).
std::vector<Geodetic> positions(const std::vector<GeoSample>& v);
/// [deg] A coordinate column holding radians: its median m read as radians (m 180/pi) lies within
/// this of the other file's median, while m as read lies farther than this from it. (Scenes are
/// tens of kilometres across: a degree of latitude is 111 km. Coordinates within about a degree
/// of 0 differ too little between the two units to be told apart, or to matter.)
inline constexpr double kRadiansMatchDeg = 1;
/// Throws ConfigError naming a latitude or longitude column of `a` or `b` that holds radians
/// (see kRadiansMatchDeg; |m| <= pi/2 for a latitude, -pi <= m <= 2 pi for a longitude). Called
/// before `near`, whose "far away" would not say which column. Empty lists pass.
void coordinates_in_degrees(const NamedPositions& a, const NamedPositions& b);

/// [m] Latitude and longitude swapped in one file: its median position as given lies farther
/// than kSwapFarM from the other file's, swapped within kSwapNearM of it. (A scene is tens of
/// kilometres across, 100 km for a landing approach; swapped coordinates of a place away from the
/// diagonal lat = lon land hundreds to thousands of kilometres off.)
inline constexpr double kSwapFarM = 300e3, kSwapNearM = 150e3;
/// Throws ConfigError naming the file of `a` or `b` whose latitude and longitude look swapped
/// (see kSwapFarM), with both distances. Which of the two: the one `third` (a third file, may
/// be null) disagrees with; without it, the one whose swap alone closes the gap, else both are
/// named (either may be swapped). Empty lists pass.
void coordinates_not_swapped(const NamedPositions& a, const NamedPositions& b, const NamedPositions* third = nullptr);

/// One time scale for the files of a recording: the times `t` of file `name` (measurements)
/// against the span of `ref` (named ref_name: the navigation or observer track they are placed
/// on). Passes when at least kMinTimeOverlap of t lies inside ref's span. Otherwise names the
/// likely cause: t scaled by 1e-3 or 1e-6 (or ref's) puts kMinTimeOverlap inside with spans
/// alike (within a factor 10: milliseconds, microseconds), or t and ref lie on different origins (one near the Unix epoch's 1e9 s, the
/// other near 0: epoch and relative), else that they do not overlap (times and spans given).
/// Spans overlapping by less (a reference that ends mid-recording) are left to the diagnosis.
inline constexpr double kMinTimeOverlap = 0.5;
void same_time_scale(const std::string& name, const std::vector<double>& t, const std::string& ref_name,
                     const std::vector<double>& ref);

/// Which heights of a track are checked against [kMinHeightM, kMaxHeightM].
enum class Heights { kAll, kWhereKnown /* finite ones: NaN marks an unknown height */, kNone };
/// A sampled track of positions, sample i named `what` + " " + i (e.g. "FILE: observer sample"):
/// its time (finite, strictly after the previous sample's), its latitude and longitude, its
/// distance from `centre` (named centre_name; nullptr: not checked), then its height as
/// `heights` says. The distance comes before the height: a local frame's origin or a
/// unit mixed up also lifts a position far up, and "far away" names the cause.
void track(const std::string& what, const std::vector<GeoSample>& v, const Geodetic* centre,
           const std::string& centre_name, Heights heights);

}  // namespace rnav::plausible
