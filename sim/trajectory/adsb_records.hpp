// ADS-B trajectory records (OpenSky / traffic "to_json(orient=records)" style): reading and
// validation. A file is a JSON array of objects, optionally gzip-compressed (.json.gz), one
// object per point in time order, with at least
//   timestamp  [ms since the Unix epoch, UTC]   latitude, longitude [deg, WGS84]
//   altitude   [ft] barometric (pressure) altitude referenced to 1013.25 hPa; 0 = ground/no data
// and optionally geoaltitude [ft] (GNSS height; null when missing). Other fields (track,
// groundspeed, vertical_rate, ...) are ignored: track in particular is int8-corrupted in some
// files, and every direction used here is computed from the positions.
#pragma once

#include "common/io/config.hpp"

#include <optional>
#include <string>
#include <vector>

namespace rnav {

struct AdsbRecord {
  std::size_t index = 0;  ///< position of the record in the file's array (0-based)
  double t_s = 0;         ///< [s] since the Unix epoch (timestamp / 1000)
  double lat_deg = 0;     ///< [deg] WGS84 latitude, [-90, 90]
  double lon_deg = 0;     ///< [deg] WGS84 longitude, [-180, 180]
  double alt_baro_ft = 0; ///< [ft] pressure altitude (1013.25 hPa); 0 = ground or no data
  std::optional<double> geoalt_ft;  ///< [ft] GNSS height, when present and not null
};

/// The whole file as text: gzip-compressed or plain (zlib reads both). Throws ConfigError.
std::string read_maybe_gzip(const std::string& file);

/// Parse and validate the records of `text` (the contents of `source`, used in messages).
/// Throws ConfigError naming the source, the record index and the field for: JSON syntax,
/// a non-array document, a non-object record, a missing, null or non-numeric required field,
/// a non-numeric geoaltitude, latitude/longitude out of range, time stamps not strictly
/// increasing.
std::vector<AdsbRecord> parse_adsb_records(const std::string& text, const std::string& source);

/// read_maybe_gzip + parse_adsb_records.
std::vector<AdsbRecord> read_adsb_file(const std::string& file);

}  // namespace rnav
