// Removing ADS-B glitches before an approach is replayed.
//
// Each record is tested in file order against the previous record P and the last KEPT record K
// (dt = t - t_K); the first rule that fires removes it:
//   1. no_height        the chosen height is absent: altitude == 0 (ground or no data) for the
//                       barometric source; geoaltitude missing/null for the GNSS source
//   2. position_stale   latitude and longitude equal P's: the position was not updated, so this
//                       record's time stamp is wrong for it (OpenSky repeats the last position)
//   3. position_jump    geodesic distance(K, record) / dt > max_speed_kt: no aircraft on an
//                       approach moves that fast; the position (or its time) is wrong
//   4. altitude_jump    |h - h_K| > max_vertical_rate_fpm * dt + altitude_tolerance_ft: a
//                       climb or descent no aircraft flies (the tolerance covers 25-ft
//                       quantisation and the second-to-second jitter of real Mode-S altitude)
// Rules 3 and 4 trust K. If they remove every record for longer than max_reject_run_s after K,
// K itself is probably the glitch: that is an error naming K (not a silent re-anchoring).
#pragma once

#include "sim/trajectory/adsb_records.hpp"

#include <map>
#include <string>
#include <vector>

namespace rnav {

enum class HeightSource { baro, geo };

struct GlitchOptions {
  HeightSource height = HeightSource::baro;  ///< which height the altitude rules test (and the replay uses)
  double max_speed_kt = 400;           ///< [kt] rule 3 limit, (0, 2000]; approach speeds are 100-200 kt
  double max_vertical_rate_fpm = 6000; ///< [ft/min] rule 4 rate, (0, 60000]; approaches descend at < 1500 ft/min
  double altitude_tolerance_ft = 300;  ///< [ft] rule 4 allowance independent of dt, [0, 10000]
  double max_reject_run_s = 60;        ///< [s] longest run of rule-3/4 removals trusted, > 0
};

struct CleanTrack {
  std::vector<AdsbRecord> kept;
  std::map<std::string, int> removed;  ///< rule name -> number of records it removed
  int removed_total() const;
};

/// The height [ft] of a record in the chosen source (geoaltitude must be present for geo).
double height_ft(const AdsbRecord& r, HeightSource s);

/// Apply the rules above. Throws ConfigError for invalid options or an untrustworthy anchor.
CleanTrack remove_glitches(const std::vector<AdsbRecord>& records, const GlitchOptions& o,
                           const std::string& source);

}  // namespace rnav
