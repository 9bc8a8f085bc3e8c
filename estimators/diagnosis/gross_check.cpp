#include "estimators/diagnosis/gross_check.hpp"

#include "common/io/config.hpp"
#include "common/physics/frames.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace rnav {

namespace {

// Least-squares slope of y on x; NaN where x spreads (sd) less than min_sd.
double slope(const std::vector<double>& x, const std::vector<double>& y, double min_sd) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  if (!(std::sqrt(sxx / n) >= min_sd)) return std::nan("");
  return sxy / sxx;
}

double mean(const std::vector<double>& x) {
  double m = 0;
  for (double v : x) m += v / static_cast<double>(x.size());
  return m;
}

double sd(const std::vector<double>& x) {
  const double m = mean(x);
  double s = 0;
  for (double v : x) s += (v - m) * (v - m) / static_cast<double>(x.size());
  return std::sqrt(s);
}

// Weighted least-squares line y = a + b x: (a, b); b not finite where x does not spread.
std::pair<double, double> line_fit(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& w) {
  double sw = 0, mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sw += w[i], mx += w[i] * x[i], my += w[i] * y[i];
  mx /= sw, my /= sw;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxx += w[i] * (x[i] - mx) * (x[i] - mx), sxy += w[i] * (x[i] - mx) * (y[i] - my);
  const double b = sxy / sxx;
  return {my - b * mx, b};
}

}  // namespace

std::string range_unit_of(double q, double tol) {
  for (const auto& [name, f] : std::vector<std::pair<const char*, double>>{
           {"kilometres", 1000}, {"feet", 0.3048}, {"nautical miles", 1852}, {"statute miles", 1609.344}, {"millimetres", 0.001}})
    if (std::abs(q * f - 1) <= tol) return name;
  return "";
}

bool outside_radians_band(double b) { return b < -kDegToRad || b > kRadiansAsDegreesRad + kDegToRad; }

bool bearings_look_like_radians(int n, int inside, int refs, int refs_outside) {
  return n >= kMinUnitSamples && inside == n && 2 * refs_outside > refs;
}

void check_plot_units(const std::vector<PlotGeometry>& plots, double azimuth_reference_deg, double radar_h_m) {
  if (plots.empty()) return;
  std::vector<double> q, dk, ek, ek_hat, eg, eg_hat;
  for (const auto& p : plots) {
    q.push_back(p.range_m / p.range_pred_m);
    dk.push_back(wrap_pi(p.course_rad - p.course_pred_rad));
    ek.push_back(p.course_rad), ek_hat.push_back(p.course_pred_rad);
    eg.push_back(p.glide_rad), eg_hat.push_back(p.glide_pred_rad);
  }
  // The course made continuous across +-pi, plot after plot (in time order): an azimuth that
  // crosses the back of the reference, or one scaled 17.45 times (milliradians in a degree
  // column), wraps, and a slope across the wrap means nothing.
  auto unwrap = [](std::vector<double>& a) {
    for (std::size_t i = 1; i < a.size(); ++i) a[i] = a[i - 1] + wrap_pi(a[i] - a[i - 1]);
  };
  unwrap(ek);
  unwrap(ek_hat);
  const std::string n = " over " + std::to_string(plots.size()) + " plots";
  // range: q = median(D / D^)
  const double qm = median(q);
  if (!(qm >= 1 / kMaxRangeScale && qm <= kMaxRangeScale)) {
    const std::string u = range_unit_of(qm);
    // No unit: a radar site of another place puts the flight far from it. A surveyed site is
    // never kSiteOffM off, nor does a radar effect move the median range that far.
    std::vector<double> d_pred, d_meas;
    for (const auto& p : plots) d_pred.push_back(p.range_pred_m), d_meas.push_back(p.range_m);
    const double mp = median(d_pred), mm = median(d_meas);
    const std::string site = u.empty() && std::abs(mp - mm) > kSiteOffM
                                 ? "; nav.csv's positions lie a median " + short_num(mp / 1000) + " km from site.json's radar, radar.csv's "
                                       "ranges a median " + short_num(mm / 1000) + " km: site.json's radar (and runway) may be another "
                                       "place's, or its position off"
                                 : std::string();
    throw ConfigError("radar.csv range_m " + (u.empty() ? std::string("does not match the nav solution's geometry")
                                                        : "looks like " + u) +
                      ": median ratio to the range from nav.csv " + short_num(qm) + n +
                      " (expected 1; a range off by more than 25 % is no radar effect)" + site);
  }
  // An angle column in another unit, from its least-squares slope b against the computed angle:
  // radians (b = pi/180), milliradians (b = 1000 pi/180 = 17.45) or radians converted twice
  // (b = 180/pi); the course's is checked before its offset, which such a scale makes large.
  auto angle_unit = [&n](const char* col, double b) {
    if (std::abs(b * 180 / M_PI - 1) <= kAngleUnitMatch)
      throw ConfigError(std::string("radar.csv ") + col + " looks like radians: least-squares slope " + short_num(b) +
                        " against the angle from nav.csv" + n + " (pi/180 = 0.01745; expected 1)");
    if (std::abs(b * 180 / (1000 * M_PI) - 1) <= kAngleUnitMatch)
      throw ConfigError(std::string("radar.csv ") + col + " looks like milliradians: least-squares slope " + short_num(b) +
                        " against the angle from nav.csv" + n + " (1000 pi/180 = 17.45; expected 1)");
    if (std::abs(b * M_PI / 180 - 1) <= kAngleUnitMatch)
      throw ConfigError(std::string("radar.csv ") + col + " looks like radians converted twice: least-squares slope " +
                        short_num(b) + " against the angle from nav.csv" + n + " (180/pi = 57.3; expected 1)");
  };
  const double b_course = slope(ek_hat, ek, kMinSpreadDeg * kDegToRad);
  if (!std::isnan(b_course)) angle_unit("azimuth_deg", b_course);
  // course: an azimuth reference read as radians, the offset, then the slope. A reference of r
  // radians written as r "degrees" (r <= 2 pi) leaves d = r - r 180/pi (wrapped; 18 deg for
  // 6.07 rad): named where d matches it and is beyond kMinRefOffsetDeg.
  const double d = median(dk) / kDegToRad;
  const double r = azimuth_reference_deg;
  const double off = std::abs(wrap_pi((d - r * (1 - 180 / M_PI)) * kDegToRad)) / kDegToRad;
  if (r >= 0 && r <= 2 * M_PI && std::abs(d) > kMinRefOffsetDeg && off <= kRefMatchDeg)
    throw ConfigError("site.json radar.azimuth_reference_deg looks like radians: " + short_num(r) + " rad is " +
                      short_num(r * 180 / M_PI) + " deg, and the azimuths are off by the difference (median " + short_num(d) +
                      " deg" + n + ")");
  if (std::abs(d) > kMaxAngleOffsetDeg)
    throw ConfigError("radar.csv azimuth_deg is off the azimuth from nav.csv and site.json by a median " + short_num(d) +
                      " deg" + n + " (more than " + short_num(kMaxAngleOffsetDeg) +
                      " deg is no radar effect): check site.json radar.azimuth_reference_deg and the column's unit");
  // Heights: the aircraft's height H = D sin(Eg) + h_R + (D cos Eg)^2 / (2 R_E) (above the radar,
  // the radar's own, the Earth's drop over the horizontal distance) from the radar, against
  // nav.csv's height h as read (not recomputed from the nav's polar position: in kilometres h is
  // a metre or so, and the recomputation's decimetre errors would hide it). An angle's slope tells
  // nothing here: near the runway the radar's height over D dominates it. By the least-squares
  // line H = c + d h over the plots:
  //   nav.csv h_m in a unit of factor f (h = H / f):       d = f, c = 0;
  //   site.json radar.h_m in that unit (h_R' = h_R / f):   d = 1, c = h_R' - h_R, the site height
  //   nav.csv implies h_R' - c, and h_R' over it is 1 / f (named where |c| > kMinSiteHeightOffsetM:
  //   an elevation bias of 0.1 deg is 17 m at 10 km).
  // Weighted by 1 / D^2: H's noise is D times the elevation's. A real elevation bias tilts the
  // line by a few per cent on a glide (0.1 deg is 3.4 % of the height on a 3 deg slope), hence
  // kHeightUnitMatch. A ratio and an offset are told apart only where the heights spread (sd of H at least
  // kMinHeightSpreadM, a descent); on a level pass nav's unit is named from the median ratio h / H.
  auto height = [&](double D, double Eg) { return D * std::sin(Eg) + radar_h_m + std::pow(D * std::cos(Eg), 2) / (2 * kEarthRadiusM); };
  std::vector<double> H, h, w, hq;
  for (const auto& p : plots) {
    H.push_back(height(p.range_m, p.glide_rad)), h.push_back(p.nav_h_m), w.push_back(1 / (p.range_m * p.range_m));
    if (H.back() >= kMinHeightM && p.nav_h_m > 0) hq.push_back(p.nav_h_m / H.back());
  }
  const auto [ch, dh] = line_fit(h, H, w);  // H = ch + dh h
  const bool spread = sd(H) >= kMinHeightSpreadM && std::isfinite(dh);
  const double q_nav = spread ? (dh != 0 ? 1 / dh : INFINITY) : hq.size() >= kMinHeightPlots ? median(hq) : 1.0;
  if (const std::string u = range_unit_of(q_nav, kHeightUnitMatch); !u.empty())
    throw ConfigError("nav.csv h_m looks like " + u + ": the aircraft's heights from nav.csv are " + short_num(q_nav) +
                      " times those from the radar's range and elevation" +
                      (spread ? " (least-squares line" + n + ")" : " (median over " + std::to_string(hq.size()) + " plots)") +
                      " (expected 1)");
  if (spread && std::abs(dh - 1) <= kHeightUnitMatch && std::abs(ch) > kMinSiteHeightOffsetM && radar_h_m != ch)
    if (const std::string u = range_unit_of(radar_h_m / (radar_h_m - ch), kHeightUnitMatch); !u.empty())
      throw ConfigError("site.json radar.h_m looks like " + u + ": " + short_num(radar_h_m) +
                        " m puts every height from the radar " + short_num(ch) + " m off nav.csv's (least-squares line" + n +
                        "); nav.csv implies a site height of " + short_num(radar_h_m - ch) + " m");
  for (const auto& [col, b] : {std::pair<const char*, double>{"azimuth_deg", b_course},
                               {"elevation_deg", slope(eg_hat, eg, kMinSpreadDeg * kDegToRad)}}) {
    if (std::isnan(b)) continue;
    angle_unit(col, b);
    if (b >= 1 / kMaxSlope && b <= kMaxSlope) continue;
    throw ConfigError(std::string("radar.csv ") + col + " does not scale with the angle from nav.csv: least-squares slope " +
                      short_num(b) + n + " (expected 1): check its unit, and nav.csv's heights");
  }
}

void check_truth_heights(const std::vector<GeoSample>& nav, const std::vector<GeoSample>& truth) {
  if (nav.size() < 2) return;
  std::vector<double> q;
  std::size_t k = 1;
  for (const auto& s : truth) {
    if (s.t_s < nav.front().t_s || s.t_s > nav.back().t_s) continue;
    while (k + 1 < nav.size() && nav[k].t_s < s.t_s) ++k;
    const GeoSample &a = nav[k - 1], &b = nav[k];
    const double w = b.t_s > a.t_s ? (s.t_s - a.t_s) / (b.t_s - a.t_s) : 0;
    const double h_nav = a.g.h_m + w * (b.g.h_m - a.g.h_m);  // h^(t) = h_a + w (h_b - h_a)
    if (h_nav >= kMinHeightM) q.push_back(s.g.h_m / h_nav);
  }
  if (q.size() < kMinHeightPlots) return;
  const double qm = median(q);
  if (qm >= 1 / kMaxRangeScale && qm <= kMaxRangeScale) return;
  const std::string u = range_unit_of(qm);
  throw ConfigError("truth.csv h_m " + (u.empty() ? std::string("does not match nav.csv's heights") : "looks like " + u) +
                    ": the aircraft's true heights are a median " + short_num(qm) + " times nav.csv's over " +
                    std::to_string(q.size()) + " samples (expected 1)");
}

}  // namespace rnav
