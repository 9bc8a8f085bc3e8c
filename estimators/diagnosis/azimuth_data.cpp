#include "estimators/diagnosis/azimuth_data.hpp"

#include "common/io/atomic_file.hpp"
#include "common/io/csv_columns.hpp"

#include "common/io/config.hpp"
#include "common/io/csv_table.hpp"
#include "common/io/plausible.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace rnav {

AzimuthData AzimuthData::read_folder(const std::string& dir) {
  AzimuthData d;
  {
    const CsvTable t = CsvTable::read(dir + "/observer.csv", {"t_s", "lat_deg", "lon_deg", "h_m"});
    t.require_time_order("t_s", false);
    for (std::size_t i = 0; i < t.rows(); ++i)
      d.observer.push_back({t.col("t_s")[i], {t.col("lat_deg")[i], t.col("lon_deg")[i], t.col("h_m")[i]}});
  }
  {
    const CsvTable t = CsvTable::read(dir + "/bearings.csv", {"t_s", "bearing_deg"});
    t.require_time_order("t_s", true);
    for (std::size_t i = 0; i < t.rows(); ++i) {
      const double ts = t.col("t_s")[i], b = t.col("bearing_deg")[i];
      if (std::abs(b) > 720)
        throw ConfigError(dir + "/bearings.csv:" + std::to_string(t.line(i)) + ": column 'bearing_deg': " +
                          value_text(b) + " is outside [-720, 720]" +
                          (std::abs(b) <= 2000 * M_PI + 1 ? " (milliradians in a degree column?)" : ""));
      if (d.frames.empty() || d.frames.back().t_s != ts) d.frames.push_back({ts, {}});
      d.frames.back().bearings_rad.push_back(wrap_pi(b * kDegToRad));
    }
  }
  if (std::filesystem::exists(dir + "/truth.csv")) {
    const CsvTable t = CsvTable::read(dir + "/truth.csv", {"t_s", "lat_deg", "lon_deg"});
    t.require_time_order("t_s", false);
    for (std::size_t i = 0; i < t.rows(); ++i)
      d.truth.push_back({t.col("t_s")[i], {t.col("lat_deg")[i], t.col("lon_deg")[i], 0.0}});
  }
  // a track of fewer fixes cannot cover the bearings (named before the time-scale check, which
  // would take 0.4 s of fixes under 300 s of bearings for bearings in milliseconds)
  if (d.observer.size() < 10)
    throw ConfigError(dir + "/observer.csv: " + std::to_string(d.observer.size()) + " fixes; the observer's track needs at least 10");
  if (d.frames.size() < 10) throw ConfigError(dir + "/bearings.csv: fewer than 10 frames");
  // coordinates in radians, named by file and column before validate's "far away"
  plausible::coordinates_in_degrees({"observer.csv lat_deg", "observer.csv lon_deg", plausible::positions(d.observer)},
                                    {"truth.csv lat_deg", "truth.csv lon_deg", plausible::positions(d.truth)});
  plausible::coordinates_not_swapped({"observer.csv lat_deg", "observer.csv lon_deg", plausible::positions(d.observer)},
                                     {"truth.csv lat_deg", "truth.csv lon_deg", plausible::positions(d.truth)});
  d.validate(dir);
  // one time scale, after each time's own checks: the frames and the truth on the observer's
  std::vector<double> obs_t, frame_t, truth_t;
  for (const auto& s : d.observer) obs_t.push_back(s.t_s);
  for (const auto& f : d.frames) frame_t.push_back(f.t_s);
  for (const auto& s : d.truth) truth_t.push_back(s.t_s);
  plausible::same_time_scale(dir + "/bearings.csv t_s", frame_t, dir + "/observer.csv t_s", obs_t);
  plausible::same_time_scale(dir + "/truth.csv t_s", truth_t, dir + "/observer.csv t_s", obs_t);
  return d;
}

void AzimuthData::validate(const std::string& source) const {
  namespace pl = plausible;
  const Geodetic* first = observer.empty() ? nullptr : &observer[0].g;
  pl::track(source + ": observer sample", observer, first, "the observer's first position", pl::Heights::kAll);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string at = source + ": bearing frame " + std::to_string(i);
    pl::time(at, frames[i].t_s);
    if (i > 0) pl::after(at, frames[i].t_s, frames[i - 1].t_s);
    for (double b : frames[i].bearings_rad) pl::angle(at, "bearing", b);
  }
  // h_m is unused in the truth (truth.csv has no height column).
  pl::track(source + ": truth sample", truth, first, "the observer's first position", pl::Heights::kNone);
}

std::vector<CsvColumnDoc> AzimuthData::observer_columns() {
  return geo_track_columns("time of validity, the data set's time scale (one for every file of the folder)",
                           "the observer's navigation solution's");
}

std::vector<CsvColumnDoc> AzimuthData::bearings_columns() {
  return {{"t_s", "s", "frame time (rows of one time: the detections of one frame)"},
          {"bearing_deg", "deg", "true bearing from the observer to the detection, clockwise from north"}};
}

std::vector<CsvColumnDoc> AzimuthData::truth_columns() {
  return geo_track_columns("time of validity, the data set's time scale", "the object's true", /*with_height=*/false);
}

void AzimuthData::write_folder(const std::string& dir) const {
  std::filesystem::create_directories(dir);
  char b[200];
  const auto write = [&](const std::string& name, const std::vector<CsvColumnDoc>& columns, const std::string& rows) {
    write_file_atomic(dir, name, csv_header(columns) + rows);
    write_csv_units(dir, name, columns);
  };
  {
    std::string f;
    for (const auto& s : observer) {
      std::snprintf(b, sizeof b, "%.6f,%.10f,%.10f,%.4f\n", s.t_s, s.g.lat_deg, s.g.lon_deg, s.g.h_m);
      f += b;
    }
    write("observer.csv", observer_columns(), f);
  }
  {
    std::string f;
    for (const auto& fr : frames)
      for (double x : fr.bearings_rad) {
        std::snprintf(b, sizeof b, "%.6f,%.6f\n", fr.t_s, x / kDegToRad);
        f += b;
      }
    write("bearings.csv", bearings_columns(), f);
  }
  if (!truth.empty()) {
    std::string f;
    for (const auto& s : truth) {
      std::snprintf(b, sizeof b, "%.6f,%.10f,%.10f\n", s.t_s, s.g.lat_deg, s.g.lon_deg);
      f += b;
    }
    write("truth.csv", truth_columns(), f);
  }
}

}  // namespace rnav
