// The CSV interchange format's reader: a header line is required, extra columns are ignored,
// every named column must be present and every cell a finite number; anything else is a
// ConfigError naming file, line and column. Rows must be in time order.
// read_columns() also reads text columns, numeric columns with empty cells (NaN) and optional
// columns that may be absent from the header.
#pragma once

#include "common/io/config.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rnav {

/// What the cells of a column must hold.
enum class CsvKind {
  kNumber,         ///< a finite number in every cell
  kNumberOrEmpty,  ///< empty (read as NaN) or a finite number
  kText,           ///< non-empty text (leading/trailing blanks trimmed; no quoting)
};

/// One column asked of CsvTable::read_columns.
struct CsvColumn {
  std::string name;                  ///< header name
  CsvKind kind = CsvKind::kNumber;   ///< what its cells must hold
  bool optional = false;             ///< may be absent from the header (then has(name) is false)
};

/// The largest CSV file read [bytes], 64 MiB by default: a stated bound, refused up front with
/// the file's size (a 237 MB radar.csv of 5.3 M plots ran 180 s and took 4.35 GB before it
/// was stopped, with no output). set_max_csv_bytes raises or lowers it (rnav_diagnose
/// --max-input-mb); > 0.
std::uint64_t max_csv_bytes();
void set_max_csv_bytes(std::uint64_t bytes);

class CsvTable {
 public:
  /// Read `file`, keeping `columns` (all required, all numbers).
  static CsvTable read(const std::string& file, const std::vector<std::string>& columns);
  /// Read `file`, keeping `columns` as each one's spec says.
  static CsvTable read_columns(const std::string& file, const std::vector<CsvColumn>& columns);
  std::size_t rows() const { return lines_.size(); }
  /// True if column `name` was asked for and is in the header.
  bool has(const std::string& name) const { return cols_.count(name) || text_.count(name); }
  /// A numeric column (kNumber or kNumberOrEmpty; NaN for empty cells).
  const std::vector<double>& col(const std::string& name) const;
  /// A text column (kText).
  const std::vector<std::string>& text(const std::string& name) const;
  /// The file's line number of row i (1-based, header = line 1).
  int line(std::size_t i) const { return lines_.at(i); }
  const std::string& file() const { return file_; }
  /// Throw naming file and line unless column `name` is increasing (strictly, or not
  /// decreasing if allow_equal).
  void require_time_order(const std::string& name, bool allow_equal) const;

 private:
  std::string file_;
  std::map<std::string, std::vector<double>> cols_;
  std::map<std::string, std::vector<std::string>> text_;
  std::vector<int> lines_;
};

}  // namespace rnav
