#include "sim/trajectory/adsb_records.hpp"

#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cmath>
#include <memory>

namespace rnav {

std::string read_maybe_gzip(const std::string& file) {
  const std::unique_ptr<gzFile_s, int (*)(gzFile)> f(gzopen(file.c_str(), "rb"), gzclose);
  if (!f) throw ConfigError(file + ": cannot open");
  std::string out;
  char buf[1 << 16];
  for (;;) {
    const int n = gzread(f.get(), buf, sizeof buf);
    if (n < 0) {
      int err = 0;
      throw ConfigError(file + ": gzip read error: " + gzerror(f.get(), &err));
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

namespace {

// A required finite number: the record's field `key`.
double required(const nlohmann::json& r, const char* key, const std::string& where) {
  const auto it = r.find(key);
  if (it == r.end()) throw ConfigError(where + ": field '" + key + "' is missing");
  if (!it->is_number())
    throw ConfigError(where + ": field '" + key + "' is not a number (got " + it->dump() + ")");
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw ConfigError(where + ": field '" + key + "' is not finite");
  return v;
}

}  // namespace

std::vector<AdsbRecord> parse_adsb_records(const std::string& text, const std::string& source) {
  nlohmann::json doc;
  doc = parse_json_checked(text, source + ": not valid JSON", /*allow_comments=*/false);
  if (!doc.is_array()) throw ConfigError(source + ": expected a JSON array of records");
  std::vector<AdsbRecord> out;
  out.reserve(doc.size());
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const auto& r = doc[i];
    const std::string where = source + ": record " + std::to_string(i);
    if (!r.is_object()) throw ConfigError(where + ": expected an object, got " + r.dump());
    AdsbRecord a;
    a.index = i;
    a.t_s = required(r, "timestamp", where) * 1e-3;
    a.lat_deg = required(r, "latitude", where);
    a.lon_deg = required(r, "longitude", where);
    a.alt_baro_ft = required(r, "altitude", where);
    if (std::abs(a.lat_deg) > 90) throw ConfigError(where + ": field 'latitude' is outside [-90, 90]");
    if (std::abs(a.lon_deg) > 180) throw ConfigError(where + ": field 'longitude' is outside [-180, 180]");
    const auto g = r.find("geoaltitude");
    if (g != r.end() && !g->is_null()) {
      if (!g->is_number() || !std::isfinite(g->get<double>()))
        throw ConfigError(where + ": field 'geoaltitude' is neither a number nor null (got " + g->dump() + ")");
      a.geoalt_ft = g->get<double>();
    }
    if (!out.empty() && !(a.t_s > out.back().t_s))
      throw ConfigError(where + ": field 'timestamp' is not after record " +
                        std::to_string(out.back().index) + "'s (records must be in time order)");
    out.push_back(a);
  }
  return out;
}

std::vector<AdsbRecord> read_adsb_file(const std::string& file) {
  return parse_adsb_records(read_maybe_gzip(file), file);
}

}  // namespace rnav
