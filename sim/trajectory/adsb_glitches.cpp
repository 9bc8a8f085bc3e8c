#include "sim/trajectory/adsb_glitches.hpp"

#include <GeographicLib/Geodesic.hpp>

#include <cmath>

namespace rnav {

namespace {
constexpr double kKnot = 1852.0 / 3600.0;  // [m/s] per knot
}

int CleanTrack::removed_total() const {
  int n = 0;
  for (const auto& [rule, k] : removed) n += k;
  return n;
}

double height_ft(const AdsbRecord& r, HeightSource s) {
  return s == HeightSource::baro ? r.alt_baro_ft : r.geoalt_ft.value();
}

CleanTrack remove_glitches(const std::vector<AdsbRecord>& records, const GlitchOptions& o,
                           const std::string& source) {
  if (!(o.max_speed_kt > 0 && o.max_speed_kt <= 2000))
    throw ConfigError("--max-speed-kt must be in (0, 2000]");
  if (!(o.max_vertical_rate_fpm > 0 && o.max_vertical_rate_fpm <= 60000))
    throw ConfigError("--max-vertical-rate-fpm must be in (0, 60000]");
  if (!(o.altitude_tolerance_ft >= 0 && o.altitude_tolerance_ft <= 10000))
    throw ConfigError("--altitude-tolerance-ft must be in [0, 10000]");
  if (!(o.max_reject_run_s > 0)) throw ConfigError("--max-reject-run-s must be positive");
  const auto& geod = GeographicLib::Geodesic::WGS84();
  CleanTrack c;
  for (const char* rule : {"no_height", "position_stale", "position_jump", "altitude_jump"})
    c.removed[rule] = 0;
  const AdsbRecord* prev = nullptr;
  for (const auto& r : records) {
    const char* why = nullptr;
    const bool has_height = o.height == HeightSource::baro ? r.alt_baro_ft != 0 : r.geoalt_ft.has_value();
    if (!has_height) {
      why = "no_height";
    } else if (prev && r.lat_deg == prev->lat_deg && r.lon_deg == prev->lon_deg) {
      why = "position_stale";
    } else if (!c.kept.empty()) {
      const AdsbRecord& k = c.kept.back();
      const double dt = r.t_s - k.t_s;
      double s12 = 0;
      geod.Inverse(k.lat_deg, k.lon_deg, r.lat_deg, r.lon_deg, s12);
      // rule 3: implied ground speed; rule 4: |dh| > rate dt + tolerance
      if (s12 / dt > o.max_speed_kt * kKnot) why = "position_jump";
      else if (std::abs(height_ft(r, o.height) - height_ft(k, o.height)) >
               o.max_vertical_rate_fpm / 60.0 * dt + o.altitude_tolerance_ft)
        why = "altitude_jump";
      if (why && dt > o.max_reject_run_s)
        throw ConfigError(source + ": every record for " + std::to_string(dt) +
                          " s after record " + std::to_string(k.index) + " jumps from it (rule " +
                          why + " at record " + std::to_string(r.index) + "); record " +
                          std::to_string(k.index) + " is probably the glitch — check it, or "
                          "raise --max-speed-kt / --max-vertical-rate-fpm / --max-reject-run-s");
    }
    prev = &r;
    if (why) ++c.removed[why];
    else c.kept.push_back(r);
  }
  return c;
}

}  // namespace rnav
