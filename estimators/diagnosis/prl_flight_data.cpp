#include "estimators/diagnosis/prl_flight_data.hpp"

#include "common/io/config.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/csv_columns.hpp"
#include "common/io/csv_table.hpp"
#include "common/io/plausible.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace rnav {

namespace {
std::vector<GeoSample> read_geo(const std::string& file) {
  const CsvTable t = CsvTable::read(file, {"t_s", "lat_deg", "lon_deg", "h_m"});
  t.require_time_order("t_s", false);
  std::vector<GeoSample> out;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double lat = t.col("lat_deg")[i], lon = t.col("lon_deg")[i];
    if (std::abs(lat) > 90 || std::abs(lon) > 360)
      throw ConfigError(file + ":" + std::to_string(t.line(i)) + ": latitude/longitude out of range");
    out.push_back({t.col("t_s")[i], {lat, lon, t.col("h_m")[i]}});
  }
  return out;
}

// dir/name: the geodetic track v of `whose` position (nav.csv, truth.csv), and its description.
void write_geo(const std::string& dir, const std::string& name, const std::vector<GeoSample>& v, const std::string& whose) {
  const auto columns = geo_track_columns("time of validity, the flight's time scale", whose);
  std::string f = csv_header(columns);
  char b[160];
  for (const auto& s : v) {
    std::snprintf(b, sizeof b, "%.6f,%.10f,%.10f,%.4f\n", s.t_s, s.g.lat_deg, s.g.lon_deg, s.g.h_m);
    f += b;
  }
  write_file_atomic(dir, name, f);
  write_csv_units(dir, name, columns);
}
// The truth against the nav solution: an aircraft's nav solution lies metres, at worst tens of
// metres, from its truth. The median horizontal distance over the nav samples inside the truth's span
// (truth interpolated linearly in the site's local frame) beyond kTruthFarM is refused; a time
// shift of the truth that brings it within kTruthNearM is named with its size (a grid of
// kShiftStepS over +-half the overlap, then refined to kShiftStepS / 100), else the distance.
constexpr double kTruthFarM = 500;      // [m] beyond any nav error the diagnosis models (an INS drift of a few hundred metres at worst)
constexpr double kTruthNearM = 50;      // [m] a shift that explains the distance brings it within this
constexpr double kShiftStepS = 1;       // [s] the shift's search grid
constexpr std::size_t kMaxPairs = 2000;  // nav samples used (evenly spaced): enough for a median
// A track in the site's local frame (computed once: the shift search evaluates it many times).
struct LocalTrack {
  std::vector<double> t;
  std::vector<Eigen::Vector3d> p;
};
LocalTrack local(const std::vector<GeoSample>& v, const LocalLevelFrame& F, std::size_t step = 1) {
  LocalTrack out;
  for (std::size_t i = 0; i < v.size(); i += step) out.t.push_back(v[i].t_s), out.p.push_back(F.from_geodetic(v[i].g));
  return out;
}
double median_truth_distance_m(const LocalTrack& nav, const LocalTrack& truth, double shift_s) {
  std::vector<double> dist;
  std::size_t k = 0;
  for (std::size_t i = 0; i < nav.t.size(); ++i) {
    const double t = nav.t[i] + shift_s;  // the truth row stamped t describes the nav sample at t - shift
    while (k + 1 < truth.t.size() && truth.t[k + 1] < t) ++k;
    if (k + 1 >= truth.t.size() || t < truth.t[k]) continue;
    const double a = (t - truth.t[k]) / (truth.t[k + 1] - truth.t[k]);
    const Eigen::Vector3d e = (1 - a) * truth.p[k] + a * truth.p[k + 1] - nav.p[i];
    dist.push_back(std::hypot(e.x(), e.z()));  // horizontal (F: x, z level, y up): heights have their own unit checks
  }
  if (dist.size() < 10) return NAN;
  std::nth_element(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(dist.size() / 2), dist.end());
  return dist[dist.size() / 2];
}
void check_truth_against_nav(const PrlFlightData& d, const std::string& dir) {
  if (d.truth.size() < 2) return;
  const LocalLevelFrame F(d.radar_site, 0.0);
  const LocalTrack nav = local(d.nav, F, std::max<std::size_t>(1, d.nav.size() / kMaxPairs)), truth = local(d.truth, F);
  const double given = median_truth_distance_m(nav, truth, 0);
  if (!(given > kTruthFarM)) return;  // near, or too little overlap to say (same_time_scale's)
  const double half = 0.5 * (std::min(d.nav.back().t_s, d.truth.back().t_s) - std::max(d.nav.front().t_s, d.truth.front().t_s));
  double best = given, best_s = 0;
  auto try_shift = [&](double s) {
    const double m = median_truth_distance_m(nav, truth, s);
    if (m < best) best = m, best_s = s;
  };
  for (double s = -half; s <= half; s += kShiftStepS) try_shift(s);
  const double coarse = best_s;
  for (double s = coarse - kShiftStepS; s <= coarse + kShiftStepS; s += kShiftStepS / 100) try_shift(s);
  char b[256];
  if (best <= kTruthNearM) {
    std::snprintf(b, sizeof b, "/truth.csv's time stamps look %+.2f s off nav.csv's (its median distance from the nav solution "
                  "%.0f m as stamped, %.1f m shifted): one time scale for every file", best_s, given, best);
    throw ConfigError(dir + b);
  }
  std::snprintf(b, sizeof b, "/truth.csv lies a median %.0f m from nav.csv's solution (no time shift brings it within %.0f m): "
                "not this flight's truth, or a nav solution far off", given, kTruthNearM);
  throw ConfigError(dir + b);
}

}  // namespace

std::vector<CsvColumnDoc> PrlFlightData::radar_columns() {
  return {{"t_s", "s", "plot time, the flight's time scale (one for every file of the folder)"},
          {"range_m", "m", "slant range from the radar antenna"},
          {"azimuth_deg", "deg",
           "azimuth in the radar's horizontal plane from the true bearing azimuth_reference_deg (site.json), clockwise positive"},
          {"elevation_deg", "deg", "elevation above the radar's local horizontal"}};
}

PrlFlightData PrlFlightData::read_folder(const std::string& dir) {
  PrlFlightData d;
  {
    const std::string file = dir + "/site.json";
    const nlohmann::json j = load_json_file(file);
    try {
      Section root(j, "");
      Section r = root.section("radar"), w = root.section("runway");
      d.radar_site = {r.required_number("lat_deg", -90, 90), r.required_number("lon_deg", -360, 360),
                      r.required_number("h_m", -500, 9000)};
      d.azimuth_reference_deg = r.required_number("azimuth_reference_deg", -360, 360);
      d.threshold = {w.required_number("threshold_lat_deg", -90, 90),
                     w.required_number("threshold_lon_deg", -360, 360),
                     w.required_number("threshold_h_m", -500, 9000)};
      d.heading_deg = w.required_number("heading_deg", -360, 360);
      r.finish();
      w.finish();
      root.finish();
    } catch (const ConfigError& e) {
      throw ConfigError(file + ": " + e.what());
    }
  }
  const CsvTable r = CsvTable::read(dir + "/radar.csv", {"t_s", "range_m", "azimuth_deg", "elevation_deg"});
  r.require_time_order("t_s", false);
  for (std::size_t i = 0; i < r.rows(); ++i) {
    if (r.col("range_m")[i] <= 0)
      throw ConfigError(dir + "/radar.csv:" + std::to_string(r.line(i)) + ": column 'range_m' must be > 0");
    if (std::abs(r.col("elevation_deg")[i]) > 90)
      throw ConfigError(dir + "/radar.csv:" + std::to_string(r.line(i)) +
                        ": column 'elevation_deg' out of [-90, 90]");
    d.t_s.push_back(r.col("t_s")[i]);
    d.plots.push_back({r.col("range_m")[i], wrap_pi(r.col("azimuth_deg")[i] * kDegToRad),
                       r.col("elevation_deg")[i] * kDegToRad});
  }
  d.nav = read_geo(dir + "/nav.csv");
  if (std::filesystem::exists(dir + "/truth.csv")) d.truth = read_geo(dir + "/truth.csv");
  if (d.plots.size() < 10) throw ConfigError(dir + "/radar.csv: fewer than 10 plots");
  if (d.nav.size() < 2) throw ConfigError(dir + "/nav.csv: fewer than 2 solutions");
  // Coordinates in radians, by file and column (before validate's "far from the radar site",
  // which would not say which column; truth's heights are checked after nav's, check_truth_heights).
  const plausible::NamedPositions site{"site.json radar.lat_deg", "site.json radar.lon_deg", {d.radar_site}};
  plausible::coordinates_in_degrees({"nav.csv lat_deg", "nav.csv lon_deg", plausible::positions(d.nav)}, site);
  plausible::coordinates_in_degrees({"truth.csv lat_deg", "truth.csv lon_deg", plausible::positions(d.truth)}, site);
  plausible::coordinates_in_degrees({"site.json runway.threshold_lat_deg", "site.json runway.threshold_lon_deg", {d.threshold}}, site);
  // latitude and longitude swapped in one file (before "far from the radar site")
  // (the third file decides which of two is swapped)
  const plausible::NamedPositions nav{"nav.csv lat_deg", "nav.csv lon_deg", plausible::positions(d.nav)};
  const plausible::NamedPositions threshold{"site.json runway.threshold_lat_deg", "site.json runway.threshold_lon_deg", {d.threshold}};
  plausible::coordinates_not_swapped(nav, site, &threshold);
  plausible::coordinates_not_swapped(threshold, site, &nav);
  plausible::coordinates_not_swapped({"truth.csv lat_deg", "truth.csv lon_deg", plausible::positions(d.truth)}, nav, &site);
  d.validate(dir);
  // one time scale, after each time's own checks: the plots (and the truth) on the nav solution's
  std::vector<double> nav_t;
  for (const auto& s : d.nav) nav_t.push_back(s.t_s);
  plausible::same_time_scale(dir + "/radar.csv t_s", d.t_s, dir + "/nav.csv t_s", nav_t);
  std::vector<double> truth_t;
  for (const auto& s : d.truth) truth_t.push_back(s.t_s);
  plausible::same_time_scale(dir + "/truth.csv t_s", truth_t, dir + "/nav.csv t_s", nav_t);
  check_truth_against_nav(d, dir);
  return d;
}

void PrlFlightData::validate(const std::string& source) const {
  namespace pl = plausible;
  pl::geodetic(source + ": the radar site", radar_site);
  pl::geodetic(source + ": the runway threshold", threshold);
  pl::near(source + ": the runway threshold", threshold, radar_site, "the radar site");
  if (t_s.size() != plots.size())
    throw std::logic_error(source + ": " + std::to_string(t_s.size()) + " plot times for " + std::to_string(plots.size()) + " plots");
  for (std::size_t i = 0; i < plots.size(); ++i) {
    const std::string at = source + ": radar plot " + std::to_string(i);
    pl::time(at, t_s[i]);
    pl::range(at, plots[i].range_m);
    pl::angle(at, "azimuth", plots[i].course_rad);
    pl::angle(at, "elevation", plots[i].glide_rad);
    if (i > 0 && t_s[i] < t_s[i - 1])
      throw ConfigError(at + ": time " + std::to_string(t_s[i]) + " s before the previous plot's " + std::to_string(t_s[i - 1]) + " s");
  }
  for (const auto* list : {&nav, &truth})
    for (std::size_t i = 0; i < list->size(); ++i) {
      const std::string at = source + (list == &nav ? ": nav solution " : ": truth sample ") + std::to_string(i);
      pl::time(at, (*list)[i].t_s);
      if (i > 0) pl::after(at, (*list)[i].t_s, (*list)[i - 1].t_s);
      pl::geodetic(at, (*list)[i].g);
      pl::near(at, (*list)[i].g, radar_site, "the radar site");
    }
}

void PrlFlightData::write_folder(const std::string& dir) const {
  std::filesystem::create_directories(dir);
  nlohmann::ordered_json j;
  j["radar"] = {{"lat_deg", radar_site.lat_deg}, {"lon_deg", radar_site.lon_deg},
                {"h_m", radar_site.h_m}, {"azimuth_reference_deg", azimuth_reference_deg}};
  j["runway"] = {{"threshold_lat_deg", threshold.lat_deg}, {"threshold_lon_deg", threshold.lon_deg},
                 {"threshold_h_m", threshold.h_m}, {"heading_deg", heading_deg}};
  write_file_atomic(dir, "site.json", j.dump(2) + "\n");
  const auto columns = radar_columns();
  std::string f = csv_header(columns);
  char b[160];
  for (std::size_t i = 0; i < plots.size(); ++i) {
    std::snprintf(b, sizeof b, "%.6f,%.4f,%.8f,%.8f\n", t_s[i], plots[i].range_m,
                  plots[i].course_rad / kDegToRad, plots[i].glide_rad / kDegToRad);
    f += b;
  }
  write_file_atomic(dir, "radar.csv", f);
  write_csv_units(dir, "radar.csv", columns);
  write_geo(dir, "nav.csv", nav, "the navigation solution's");
  if (!truth.empty()) write_geo(dir, "truth.csv", truth, "the aircraft's true");
}

}  // namespace rnav
