#include "sim/trajectory/adsb_approaches.hpp"

#include "common/io/atomic_file.hpp"

#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace rnav {

namespace {
constexpr double kFt = 0.3048;  // [m] per foot

double wrap180(double a) { return std::remainder(a, 360.0); }

// Least squares y = a + b x over the given points: returns (a, b).
std::pair<double, double> line_fit(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i];
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  const double b = sxy / sxx;
  return {my - b * mx, b};
}

std::string utc(double t_s) {
  const std::time_t t = static_cast<std::time_t>(std::floor(t_s));
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}
}  // namespace

std::vector<Approach> find_approaches(const std::vector<AdsbRecord>& kept, const ApproachSearchOptions& o) {
  if (!(o.course_tolerance_deg > 0 && o.course_tolerance_deg <= 90))
    throw ConfigError("--course-tolerance-deg must be in (0, 90]");
  if (!(o.heading_deg >= 0 && o.heading_deg < 360)) throw ConfigError("--heading-deg must be in [0, 360)");
  if (!(o.min_descent_m > 0 && o.min_duration_s > 0 && o.max_gap_s > 0))
    throw ConfigError("--min-descent-m, --min-duration-s and --max-gap-s must be positive");
  const auto& geod = GeographicLib::Geodesic::WGS84();
  const LocalLevelFrame L(o.threshold, std::fmod(o.heading_deg + 180.0, 360.0));
  const std::size_t n = kept.size();
  std::vector<Approach> out;
  if (n < 3) return out;
  // Course from the neighbours (ignores the records' own track field).
  std::vector<bool> on(n);
  for (std::size_t i = 0; i < n; ++i) {
    const AdsbRecord& a = kept[i == 0 ? 0 : i - 1];
    const AdsbRecord& b = kept[i + 1 == n ? n - 1 : i + 1];
    double s12 = 0, azi1 = 0, azi2 = 0;
    geod.Inverse(a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg, s12, azi1, azi2);
    on[i] = s12 > 0 && std::abs(wrap180(azi1 - o.heading_deg)) <= o.course_tolerance_deg;
  }
  auto h_ft = [&](std::size_t i) { return height_ft(kept[i], o.height); };
  std::size_t i = 0;
  while (i < n) {
    if (!on[i]) { ++i; continue; }
    std::size_t j = i;  // run [i, j]
    while (j + 1 < n && on[j + 1] && kept[j + 1].t_s - kept[j].t_s <= o.max_gap_s) ++j;
    std::size_t low = i;
    for (std::size_t k = i; k <= j; ++k)
      if (h_ft(k) < h_ft(low)) low = k;
    const double descent_m = (h_ft(i) - h_ft(low)) * kFt;
    if (descent_m >= o.min_descent_m && kept[low].t_s - kept[i].t_s >= o.min_duration_s) {
      Approach a;
      a.first = i;
      a.last = low;
      a.t_start_s = kept[i].t_s;
      a.t_end_s = kept[low].t_s;
      a.h_start_ft = h_ft(i);
      a.h_min_ft = h_ft(low);
      geod.Inverse(o.threshold.lat_deg, o.threshold.lon_deg, kept[i].lat_deg, kept[i].lon_deg, a.dist_start_m);
      geod.Inverse(o.threshold.lat_deg, o.threshold.lon_deg, kept[low].lat_deg, kept[low].lon_deg, a.dist_end_m);
      // Points in L with the height offset 0 (a height shift moves y by the same amount to
      // within 1e-5 relative over 30 km, so the fit below can add it afterwards).
      std::vector<Eigen::Vector3d> p(low - i + 1);
      double zsum = 0;
      for (std::size_t k = i; k <= low; ++k) {
        p[k - i] = L.from_geodetic({kept[k].lat_deg, kept[k].lon_deg, h_ft(k) * kFt});
        zsum += p[k - i].z();
      }
      a.x_start_m = p.front().x();
      a.x_end_m = p.back().x();
      a.lateral_mean_m = zsum / static_cast<double>(p.size());
      double zz = 0;
      for (const auto& q : p) zz += (q.z() - a.lateral_mean_m) * (q.z() - a.lateral_mean_m);
      a.lateral_rms_m = std::sqrt(zz / static_cast<double>(p.size()));
      // Glide path: middle 80 % of the descent; y = a0 + b x; offset = TCH - a0.
      const double top = h_ft(i) * kFt - 0.1 * descent_m, bottom = h_ft(low) * kFt + 0.1 * descent_m;
      std::vector<double> xs, ys;
      for (std::size_t k = i; k <= low; ++k) {
        const double h = h_ft(k) * kFt;
        if (h <= top && h >= bottom) xs.push_back(p[k - i].x()), ys.push_back(p[k - i].y());
      }
      if (xs.size() >= 5) {
        const auto [a0, b] = line_fit(xs, ys);
        a.glide_deg = std::atan(b) / kDegToRad;
        a.fitted_offset_m = o.glide_path_tch_m - a0;
      }
      a.offset_m = o.height_offset_m ? *o.height_offset_m
                                     : a.fitted_offset_m.value_or(std::numeric_limits<double>::quiet_NaN());
      out.push_back(a);
    }
    i = j + 1;
  }
  return out;
}

void print_approach_table(std::ostream& os, const std::vector<Approach>& as) {
  os << "  #  start (UTC)           end (UTC)             dur_s  h_start_ft  h_min_ft  dist_start_m  dist_end_m"
        "  x_end_m  lat_mean_m  lat_rms_m  glide_deg  offset_m\n";
  int k = 0;
  for (const auto& a : as) {
    std::ostringstream l;
    l << std::fixed << std::setw(3) << ++k << "  " << utc(a.t_start_s) << "  " << utc(a.t_end_s) << "  "
      << std::setw(5) << std::setprecision(0) << a.t_end_s - a.t_start_s << "  " << std::setw(10)
      << a.h_start_ft << "  " << std::setw(8) << a.h_min_ft << "  " << std::setw(12) << a.dist_start_m
      << "  " << std::setw(10) << a.dist_end_m << "  " << std::setw(7) << a.x_end_m << "  " << std::setw(10) << std::setprecision(1)
      << a.lateral_mean_m << "  " << std::setw(9) << a.lateral_rms_m << "  " << std::setw(9)
      << std::setprecision(2);
    if (a.glide_deg) l << *a.glide_deg; else l << "n/a";
    l << "  " << std::setw(8) << std::setprecision(1);
    if (std::isfinite(a.offset_m)) l << a.offset_m; else l << "n/a";
    os << l.str() << "\n";
  }
}

std::vector<CsvColumnDoc> replay_csv_columns() {
  auto c = geo_track_columns("time since the first written ADS-B point", "the aircraft's ADS-B");
  c.back().meaning += ": its altitude (ft * 0.3048) plus the approach's height offset";
  return c;
}

std::size_t write_replay_csv(const std::string& file, const std::vector<AdsbRecord>& kept,
                             const Approach& a, const ApproachSearchOptions& so,
                             const ReplayExportOptions& e) {
  const double lead_s = e.lead_s;
  const HeightSource height = so.height;
  if (!std::isfinite(a.offset_m))
    throw ConfigError("the approach's height offset could not be fitted (fewer than 5 points on its "
                      "descent); give --height-offset-m");
  if (!(lead_s >= 0)) throw ConfigError("--lead-s must be >= 0");
  std::size_t first = a.first;
  while (first > 0 && kept[first - 1].t_s >= a.t_start_s - lead_s) --first;
  const LocalLevelFrame L(so.threshold, std::fmod(so.heading_deg + 180.0, 360.0));
  std::size_t last = a.first;
  auto x_of = [&](const AdsbRecord& r) {  // x in L at the exported height
    return L.from_geodetic({r.lat_deg, r.lon_deg, height_ft(r, height) * kFt + a.offset_m}).x();
  };
  while (last < a.last && x_of(kept[last + 1]) >= e.end_x_m)
    ++last;
  if (last - first + 1 < 3)
    throw ConfigError("fewer than 3 points of the approach lie before --end-x-m");
  const auto columns = replay_csv_columns();
  std::ostringstream o;
  o << csv_header(columns) << std::fixed;
  for (std::size_t k = first; k <= last; ++k)
    o << std::setprecision(3) << kept[k].t_s - kept[first].t_s << "," << std::setprecision(9)
      << kept[k].lat_deg << "," << kept[k].lon_deg << "," << std::setprecision(3)
      << height_ft(kept[k], height) * kFt + a.offset_m << "\n";
  const std::filesystem::path f(file);
  try {
    write_file_atomic(f.has_parent_path() ? f.parent_path().string() : ".", f.filename().string(), o.str());
    write_csv_units(file, columns);
  } catch (const std::exception& e) {
    throw ConfigError(file + ": cannot write: " + e.what());
  }
  return last - first + 1;
}

}  // namespace rnav
