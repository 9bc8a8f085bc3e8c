// The column descriptions of the CSV files the project writes. Every writer states its columns
// once, as a list of CsvColumnDoc, and takes from that one list both the CSV's header line
// (plain names: letters, digits and '_', a unit suffix where there is one: range_m, t_s) and the
// file NAME.units.json beside NAME.csv, which describes each column in the header's order:
//
//   {
//    "t_s": {"unit": "s", "meaning": "time since the flight's start"},
//    "n": {"unit": "", "meaning": "realizations averaged"}
//   }
//
// so that numpy.genfromtxt(names=True) and pandas read the CSV as it is, and a user (or
// scripts/rnav/csvio.py, which writes and reads the same description) learns each column's unit
// and meaning. A bad list (a name that is not plain, a name given twice, an empty meaning) is a
// programming error, checked on every use: std::invalid_argument naming the column.
#pragma once

#include <string>
#include <vector>

namespace rnav {

/// One column of a CSV file the project writes. (Not CsvColumn: that is a column asked of the
/// reader, csv_table.hpp.)
struct CsvColumnDoc {
  std::string name;     ///< header name: [A-Za-z_][A-Za-z0-9_]*, unique within its file
  /// Unit of its values: "m", "s", "deg", "rad", "m/s", "rad/s", "m^2", ...; "" for a count, an
  /// index, a flag (1/0), a name or a dimensionless ratio.
  std::string unit;
  /// What the value is, a short English phrase, non-empty (not only blanks); the frame and axis
  /// where relevant, e.g. "APOI error along X (landing frame), ensemble mean".
  std::string meaning;
};

/// Throw std::invalid_argument naming the column (its 1-based position and name) unless every
/// name is plain ([A-Za-z_][A-Za-z0-9_]*) and unique and every meaning non-empty; also for an
/// empty list.
void check_csv_columns(const std::vector<CsvColumnDoc>& columns);

/// The header line: the names joined by ',', then "\n". Checks the list (check_csv_columns).
std::string csv_header(const std::vector<CsvColumnDoc>& columns);

/// The names of a header line (the text up to the first newline, split at ','; a trailing '\r'
/// dropped); no check of the names.
std::vector<std::string> csv_header_names(const std::string& header_line);

/// NAME.units.json's text: one object, keys the column names in the header's order, each
/// {"unit": text, "meaning": text}, one column per line (see the file comment), ending in a
/// newline. Checks the list (check_csv_columns).
std::string csv_units_json(const std::vector<CsvColumnDoc>& columns);

/// The description's file name beside a CSV: "X.csv" -> "X.units.json" (a name that does not
/// end in ".csv": name + ".units.json"; a folder part is kept: "d/X.csv" -> "d/X.units.json").
std::string csv_units_name(const std::string& csv_name);

/// Write dir/csv_units_name(csv_name) with csv_units_json(columns) through write_file_atomic
/// (atomic_file.hpp: a partial file renamed into place; failures throw naming the file).
void write_csv_units(const std::string& dir, const std::string& csv_name, const std::vector<CsvColumnDoc>& columns);
/// The same beside the CSV file at `csv_path` (its folder: the path's parent, or ".").
void write_csv_units(const std::string& csv_path, const std::vector<CsvColumnDoc>& columns);

/// The columns of a geodetic track (GeoSample, frames.hpp), the project's one layout of it:
///   t_s      [s]    time of validity; `time_meaning` says in which time scale (e.g. "plot time, the
///                   flight's time scale")
///   lat_deg  [deg]  WGS84 latitude of `whose` position (e.g. "the navigation solution's"), north positive
///   lon_deg  [deg]  WGS84 longitude, east positive
///   h_m      [m]    height above the WGS84 ellipsoid (only if with_height)
std::vector<CsvColumnDoc> geo_track_columns(const std::string& time_meaning, const std::string& whose,
                                            bool with_height = true);

}  // namespace rnav
