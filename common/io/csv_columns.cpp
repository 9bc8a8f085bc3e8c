#include "common/io/csv_columns.hpp"

#include "common/io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <stdexcept>

namespace rnav {

namespace {

bool plain_name(const std::string& s) {
  if (s.empty()) return false;
  const auto letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  if (!letter(s[0])) return false;
  for (char c : s)
    if (!letter(c) && !(c >= '0' && c <= '9')) return false;
  return true;
}

std::string which(std::size_t i, const std::string& name) {
  return "CSV column " + std::to_string(i + 1) + " '" + name + "'";
}

// A JSON string literal (escaped, non-ASCII as \u escapes, as Python's json.dump writes it).
std::string literal(const std::string& s, std::size_t i, const std::string& name) {
  try {
    return nlohmann::json(s).dump(-1, ' ', true);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(which(i, name) + ": not UTF-8 text (" + e.what() + ")");
  }
}

}  // namespace

void check_csv_columns(const std::vector<CsvColumnDoc>& columns) {
  if (columns.empty()) throw std::invalid_argument("a CSV file needs at least one column");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const CsvColumnDoc& c = columns[i];
    if (!plain_name(c.name))
      throw std::invalid_argument(which(i, c.name) + ": not a plain name (letters, digits and '_', not starting with a digit)");
    if (!seen.insert(c.name).second) throw std::invalid_argument(which(i, c.name) + ": the name is given twice");
    if (c.meaning.find_first_not_of(" \t\r\n") == std::string::npos)
      throw std::invalid_argument(which(i, c.name) + ": no meaning given");
  }
}

std::string csv_header(const std::vector<CsvColumnDoc>& columns) {
  check_csv_columns(columns);
  std::string h;
  for (const auto& c : columns) h += (h.empty() ? "" : ",") + c.name;
  return h + "\n";
}

std::vector<std::string> csv_header_names(const std::string& header_line) {
  std::string line = header_line.substr(0, header_line.find('\n'));
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const auto comma = line.find(',', at);
    out.push_back(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return out;
}

std::string csv_units_json(const std::vector<CsvColumnDoc>& columns) {
  check_csv_columns(columns);
  std::string j = "{\n";
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const CsvColumnDoc& c = columns[i];
    j += " " + literal(c.name, i, c.name) + ": {\"unit\": " + literal(c.unit, i, c.name) +
         ", \"meaning\": " + literal(c.meaning, i, c.name) + "}" + (i + 1 < columns.size() ? "," : "") + "\n";
  }
  return j + "}\n";
}

std::string csv_units_name(const std::string& csv_name) {
  const std::string ext = ".csv";
  const bool csv = csv_name.size() > ext.size() && csv_name.compare(csv_name.size() - ext.size(), ext.size(), ext) == 0;
  return (csv ? csv_name.substr(0, csv_name.size() - ext.size()) : csv_name) + ".units.json";
}

void write_csv_units(const std::string& dir, const std::string& csv_name, const std::vector<CsvColumnDoc>& columns) {
  write_file_atomic(dir, csv_units_name(csv_name), csv_units_json(columns));
}

void write_csv_units(const std::string& csv_path, const std::vector<CsvColumnDoc>& columns) {
  write_file_atomic(csv_units_name(csv_path), csv_units_json(columns));
}

std::vector<CsvColumnDoc> geo_track_columns(const std::string& time_meaning, const std::string& whose, bool with_height) {
  std::vector<CsvColumnDoc> c{{"t_s", "s", time_meaning},
                              {"lat_deg", "deg", "WGS84 latitude of " + whose + " position, north positive"},
                              {"lon_deg", "deg", "WGS84 longitude of " + whose + " position, east positive"}};
  if (with_height) c.push_back({"h_m", "m", "height of " + whose + " position above the WGS84 ellipsoid"});
  return c;
}

}  // namespace rnav
