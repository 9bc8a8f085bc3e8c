#include "common/io/plausible.hpp"

#include "common/io/config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace rnav::plausible {

namespace {

std::string num(double x) { return value_text(x); }

constexpr double kPi = 3.14159265358979323846;

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Distance along the surface [m] (haversine on the WGS84 equatorial radius: enough for a bound).
double surface_distance_m(double lat1, double lon1, double lat2, double lon2) {
  constexpr double kR = 6378137.0, kDeg = 3.14159265358979323846 / 180;
  const double dlat = (lat1 - lat2) * kDeg, dlon = (lon1 - lon2) * kDeg;
  const double a = std::pow(std::sin(dlat / 2), 2) + std::cos(lat1 * kDeg) * std::cos(lat2 * kDeg) * std::pow(std::sin(dlon / 2), 2);
  return 2 * kR * std::asin(std::min(1.0, std::sqrt(a)));
}

// The median latitude and longitude [deg] of a file's positions (each coordinate's own median).
std::array<double, 2> median_position(const NamedPositions& p) {
  std::vector<double> lat, lon;
  for (const auto& g : p.g) lat.push_back(g.lat_deg), lon.push_back(g.lon_deg);
  return {median_of(lat), median_of(lon)};
}

}  // namespace

void time(const std::string& where, double t_s) {
  if (!std::isfinite(t_s) || std::abs(t_s) > kMaxAbsTimeS)
    throw ConfigError(where + ": time " + num(t_s) + " s is not finite or beyond +-" + num(kMaxAbsTimeS) + " s");
}

void geodetic(const std::string& where, const Geodetic& g, bool check_height) {
  if (!std::isfinite(g.lat_deg) || std::abs(g.lat_deg) > 90)
    throw ConfigError(where + ": latitude " + num(g.lat_deg) + " deg outside [-90, 90]");
  if (!std::isfinite(g.lon_deg) || g.lon_deg < -180 || g.lon_deg > 360)
    throw ConfigError(where + ": longitude " + num(g.lon_deg) + " deg outside [-180, 360]");
  if (check_height && (!std::isfinite(g.h_m) || g.h_m < kMinHeightM || g.h_m > kMaxHeightM))
    throw ConfigError(where + ": height " + num(g.h_m) + " m outside [" + num(kMinHeightM) + ", " + num(kMaxHeightM) + "]");
}

void range(const std::string& where, double range_m) {
  if (!std::isfinite(range_m) || range_m <= 0 || range_m > kMaxRangeM)
    throw ConfigError(where + ": range " + num(range_m) + " m outside (0, " + num(kMaxRangeM) + "]");
}

void after(const std::string& where, double t_s, double prev_t_s) {
  if (!(t_s > prev_t_s))
    throw ConfigError(where + ": time " + num(t_s) + " s is not after the previous sample's " + num(prev_t_s) + " s");
}

void angle(const std::string& where, const std::string& name, double rad) {
  if (!std::isfinite(rad) || std::abs(rad) > kMaxAbsAngleRad) {
    // a degree column holding milliradians (up to 6283, 17.5 turns read as degrees)
    const double as_deg = std::abs(rad) * 180 / 3.14159265358979323846;
    const bool mrad = std::isfinite(rad) && as_deg <= 2000 * 3.14159265358979323846 + 1;
    throw ConfigError(where + ": " + name + " " + num(rad) + " rad is not finite or beyond two turns" +
                      (mrad ? " (" + num(as_deg) + " in a degree column: milliradians?)" : ""));
  }
}

void near(const std::string& where, const Geodetic& g, const Geodetic& c, const std::string& centre_name) {
  const double d = surface_distance_m(g.lat_deg, g.lon_deg, c.lat_deg, c.lon_deg);
  // degrees columns holding radians put a position within (+-pi/2, +-pi) of (0, 0)
  const bool radians = std::abs(g.lat_deg) <= 1.5708 && std::abs(g.lon_deg) <= 3.1416 &&
                       (std::abs(c.lat_deg) > 1.5708 || std::abs(c.lon_deg) > 3.1416);
  // exactly (0, 0): what a receiver without a fix writes, not a position in radians
  const bool no_fix = (g.lat_deg == 0 && g.lon_deg == 0) || (c.lat_deg == 0 && c.lon_deg == 0);
  if (!(d <= kMaxSceneDistanceM))
    throw ConfigError(where + ": position (" + num(g.lat_deg) + ", " + num(g.lon_deg) + ") is " + num(d / 1000) +
                      " km from " + centre_name + " (" + num(c.lat_deg) + ", " + num(c.lon_deg) + "), more than " +
                      num(kMaxSceneDistanceM / 1000) + " km: " +
                      (no_fix    ? "(0, 0) is what a receiver without a fix writes: leave such samples out"
                       : radians ? "lat_deg and lon_deg look like radians"
                                 : "latitude and longitude swapped, or another place"));
}


void coordinates_not_swapped(const NamedPositions& a, const NamedPositions& b, const NamedPositions* third) {
  if (a.g.empty() || b.g.empty()) return;
  const auto pa = median_position(a), pb = median_position(b);
  const double given = surface_distance_m(pa[0], pa[1], pb[0], pb[1]);
  if (!(given > kSwapFarM)) return;
  // either file swapped; each only where its longitude can be a latitude
  const double swapped_a = std::abs(pa[1]) <= 90 ? surface_distance_m(pa[1], pa[0], pb[0], pb[1]) : HUGE_VAL;
  const double swapped_b = std::abs(pb[1]) <= 90 ? surface_distance_m(pa[0], pa[1], pb[1], pb[0]) : HUGE_VAL;
  const double swapped = std::min(swapped_a, swapped_b);
  if (!(swapped <= kSwapNearM)) return;
  char km[160];
  std::snprintf(km, sizeof km, "their median positions lie %.1f km apart as given, %.1f km with latitude and longitude swapped", given / 1000,
                swapped / 1000);
  // which one: the one a third file disagrees with, else the one whose swap alone closes the gap
  int blame = swapped_a <= kSwapNearM && swapped_b <= kSwapNearM ? -1 : swapped_a <= kSwapNearM ? 0 : 1;
  if (third && !third->g.empty()) {
    const auto pt = median_position(*third);
    const bool a_ok = surface_distance_m(pa[0], pa[1], pt[0], pt[1]) <= kSwapNearM;
    const bool b_ok = surface_distance_m(pb[0], pb[1], pt[0], pt[1]) <= kSwapNearM;
    if (a_ok != b_ok) blame = a_ok ? 1 : 0;
  }
  if (blame < 0)
    throw ConfigError(a.lat_name + "/" + a.lon_name + " or " + b.lat_name + "/" + b.lon_name + " look swapped: " + km +
                      " (either file; which one these files cannot tell)");
  const NamedPositions& x = blame == 0 ? a : b;
  const NamedPositions& y = blame == 0 ? b : a;
  throw ConfigError(x.lat_name + " and " + x.lon_name + " look swapped against " + y.lat_name + " and " + y.lon_name + ": " + km +
                    (third && !third->g.empty() ? " (" + third->lat_name + " agrees with " + y.lat_name + ")" : std::string()));
}

void same_time_scale(const std::string& name, const std::vector<double>& t, const std::string& ref_name,
                     const std::vector<double>& ref) {
  if (t.empty() || ref.size() < 2) return;
  const auto [lo_it, hi_it] = std::minmax_element(ref.begin(), ref.end());
  const double lo = *lo_it, hi = *hi_it;
  // the share of t inside ref's span when t is multiplied by s_t and ref by s_r
  auto inside = [&](double s_t, double s_r) {
    std::size_t n = 0;
    for (double x : t) n += x * s_t >= lo * s_r && x * s_t <= hi * s_r;
    return static_cast<double>(n) / static_cast<double>(t.size());
  };
  const double as_given = inside(1, 1);
  if (as_given >= kMinTimeOverlap) return;
  const auto [t_lo_it, t_hi_it] = std::minmax_element(t.begin(), t.end());
  const std::string spans = name + " runs " + num(*t_lo_it) + " to " + num(*t_hi_it) + " s, " + ref_name + " " + num(lo) + " to " +
                            num(hi) + " s";
  struct Unit {
    double s_t, s_r;
    const char* said;
  };
  const Unit units[] = {{1e-3, 1, " looks like milliseconds"}, {1e-6, 1, " looks like microseconds"},
                        {1, 1e-3, " looks like seconds where the other is in milliseconds"},
                        {1, 1e-6, " looks like seconds where the other is in microseconds"}};
  // a unit explains the mismatch when, scaled, the rows fall inside and the two spans are alike
  // (within kSpanRatio of each other): a time 2 h late, scaled by 1e-3, lands inside too, as a
  // few seconds' sliver
  constexpr double kSpanRatio = 10;
  const double t_span = *t_hi_it - *t_lo_it, r_span = hi - lo;
  auto alike = [&](const Unit& u) {
    const double a = t_span * u.s_t, b = r_span * u.s_r;
    return a * kSpanRatio >= b && b * kSpanRatio >= a;
  };
  for (const Unit& u : units)
    if (alike(u) && inside(u.s_t, u.s_r) >= kMinTimeOverlap)
      throw ConfigError(name + u.said + " (" + spans + "; scaled, " + num(100 * inside(u.s_t, u.s_r)) +
                        " % of its rows fall inside): one time scale, in seconds, for every file");
  // epoch (Unix seconds, 1e9 and more) against relative (from 0)
  constexpr double kEpochS = 1e8;  // [s] 1973: a recording's times from the Unix epoch lie beyond this
  const double t_mid = median_of(t), r_mid = median_of(ref);
  if ((std::abs(t_mid) >= kEpochS) != (std::abs(r_mid) >= kEpochS))
    throw ConfigError(name + " and " + ref_name + " are on different time origins (" + spans + "): " +
                      (std::abs(t_mid) >= kEpochS ? name : ref_name) + " looks like Unix epoch seconds, the other relative: "
                      "one time scale for every file");
  if (as_given == 0)
    throw ConfigError(name + "'s times do not overlap " + ref_name + "'s (" + spans + "; no unit or origin explains it): "
                      "one time scale for every file, or a reference of this recording");
}

std::vector<Geodetic> positions(const std::vector<GeoSample>& v) {
  std::vector<Geodetic> g;
  g.reserve(v.size());
  for (const auto& s : v) g.push_back(s.g);
  return g;
}

void coordinates_in_degrees(const NamedPositions& a, const NamedPositions& b) {
  if (a.g.empty() || b.g.empty()) return;
  // m read as radians lands on the other list's median `other`, within [lo, hi] of a radians column
  auto radians = [](double m, double other, double lo, double hi) {
    return m >= lo && m <= hi && std::abs(m * 180 / kPi - other) <= kRadiansMatchDeg && std::abs(m - other) > kRadiansMatchDeg;
  };
  const auto ma = median_position(a), mb = median_position(b);
  const double lat[2] = {ma[0], mb[0]};
  const double lon[2] = {ma[1], mb[1]};
  const NamedPositions* p[2] = {&a, &b};
  for (int i = 0; i < 2; ++i) {
    const int o = 1 - i;
    const bool r_lat = radians(lat[i], lat[o], -kPi / 2, kPi / 2), r_lon = radians(lon[i], lon[o], -kPi, 2 * kPi);
    if (!r_lat && !r_lon) continue;
    std::string names, said;
    auto add = [&](bool on, const std::string& name, double m, double other, const std::string& other_name) {
      if (!on) return;
      names += (names.empty() ? "" : " and ") + name;
      said += (said.empty() ? "" : "; ") + std::string("its median ") + num(m) + " read as radians is " +
              num(m * 180 / kPi) + " deg, where " + other_name + " lies (median " + num(other) + " deg; read as degrees it is " +
              num(std::abs(m - other)) + " deg away)";
    };
    add(r_lat, p[i]->lat_name, lat[i], lat[o], p[o]->lat_name);
    add(r_lon, p[i]->lon_name, lon[i], lon[o], p[o]->lon_name);
    throw ConfigError(names + (r_lat && r_lon ? " look" : " looks") + " like radians: " + said);
  }
}

void track(const std::string& what, const std::vector<GeoSample>& v, const Geodetic* centre,
           const std::string& centre_name, Heights heights) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string at = what + " " + std::to_string(i);
    time(at, v[i].t_s);
    if (i > 0) after(at, v[i].t_s, v[i - 1].t_s);
    geodetic(at, v[i].g, false);
    if (centre) near(at, v[i].g, *centre, centre_name);
    if (heights == Heights::kAll || (heights == Heights::kWhereKnown && !std::isnan(v[i].g.h_m))) geodetic(at, v[i].g);
  }
}

}  // namespace rnav::plausible
