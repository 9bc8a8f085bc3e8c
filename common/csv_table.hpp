// The CSV interchange format's reader: a header line is required, extra columns are ignored,
// every named column must be present and every cell a finite number; anything else is a
// ConfigError naming file, line and column. Rows must be in time order.
#pragma once

#include "config.hpp"

#include <map>
#include <string>
#include <vector>

namespace rnav {

class CsvTable {
 public:
  /// Read `file`, keeping `columns` (all required).
  static CsvTable read(const std::string& file, const std::vector<std::string>& columns);
  std::size_t rows() const { return lines_.size(); }
  const std::vector<double>& col(const std::string& name) const;
  /// The file's line number of row i (1-based, header = line 1).
  int line(std::size_t i) const { return lines_.at(i); }
  const std::string& file() const { return file_; }
  /// Throw naming file and line unless column `name` is increasing (strictly, or not
  /// decreasing if allow_equal).
  void require_time_order(const std::string& name, bool allow_equal) const;

 private:
  std::string file_;
  std::map<std::string, std::vector<double>> cols_;
  std::vector<int> lines_;
};

}  // namespace rnav
