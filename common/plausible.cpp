#include "plausible.hpp"

#include "config.hpp"

#include <algorithm>
#include <cmath>

namespace rnav::plausible {

namespace {

std::string num(double x) { return value_text(x); }

constexpr double kPi = 3.14159265358979323846;

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
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
  constexpr double kR = 6378137.0, kDeg = 3.14159265358979323846 / 180;
  const double dlat = (g.lat_deg - c.lat_deg) * kDeg, dlon = (g.lon_deg - c.lon_deg) * kDeg;
  const double a = std::pow(std::sin(dlat / 2), 2) +
                   std::cos(g.lat_deg * kDeg) * std::cos(c.lat_deg * kDeg) * std::pow(std::sin(dlon / 2), 2);
  const double d = 2 * kR * std::asin(std::min(1.0, std::sqrt(a)));
  // degrees columns holding radians put a position within (+-pi/2, +-pi) of (0, 0)
  const bool radians = std::abs(g.lat_deg) <= 1.5708 && std::abs(g.lon_deg) <= 3.1416 &&
                       (std::abs(c.lat_deg) > 1.5708 || std::abs(c.lon_deg) > 3.1416);
  if (!(d <= kMaxSceneDistanceM))
    throw ConfigError(where + ": position (" + num(g.lat_deg) + ", " + num(g.lon_deg) + ") is " + num(d / 1000) +
                      " km from " + centre_name + " (" + num(c.lat_deg) + ", " + num(c.lon_deg) + "), more than " +
                      num(kMaxSceneDistanceM / 1000) + " km: " +
                      (radians ? "lat_deg and lon_deg look like radians" : "latitude and longitude swapped, or another place"));
}

std::vector<Geodetic> positions(const std::vector<GeoSample>& v) {
  std::vector<Geodetic> g;
  g.reserve(v.size());
  for (const auto& s : v) g.push_back(s.g);
  return g;
}

void coordinates_in_degrees(const NamedPositions& a, const NamedPositions& b) {
  if (a.g.empty() || b.g.empty()) return;
  auto med = [](const NamedPositions& p, double Geodetic::*field) {
    std::vector<double> v;
    for (const auto& g : p.g) v.push_back(g.*field);
    return median_of(v);
  };
  // m read as radians lands on the other list's median `other`, within [lo, hi] of a radians column
  auto radians = [](double m, double other, double lo, double hi) {
    return m >= lo && m <= hi && std::abs(m * 180 / kPi - other) <= kRadiansMatchDeg && std::abs(m - other) > kRadiansMatchDeg;
  };
  const double lat[2] = {med(a, &Geodetic::lat_deg), med(b, &Geodetic::lat_deg)};
  const double lon[2] = {med(a, &Geodetic::lon_deg), med(b, &Geodetic::lon_deg)};
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
