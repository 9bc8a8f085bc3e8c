#include "common/io/csv_table.hpp"

#include "common/io/decimal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace rnav {

namespace {
std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}
// The first byte offset of `text` that is not valid UTF-8 (RFC 3629: no overlong forms, no
// surrogates, at most U+10FFFF), or npos.
std::size_t invalid_utf8_at(const std::string& text) {
  const auto* b = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    if (c < 0x80) { ++i; continue; }
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the second byte's range
    if (c >= 0xC2 && c <= 0xDF) len = 2;
    else if (c == 0xE0) len = 3, lo = 0xA0;
    else if (c >= 0xE1 && c <= 0xEC) len = 3;
    else if (c == 0xED) len = 3, hi = 0x9F;
    else if (c >= 0xEE && c <= 0xEF) len = 3;
    else if (c == 0xF0) len = 4, lo = 0x90;
    else if (c >= 0xF1 && c <= 0xF3) len = 4;
    else if (c == 0xF4) len = 4, hi = 0x8F;
    else return i;
    if (i + len > n || b[i + 1] < lo || b[i + 1] > hi) return i;
    for (std::size_t k = 2; k < len; ++k)
      if (b[i + k] < 0x80 || b[i + k] > 0xBF) return i;
    i += len;
  }
  return std::string::npos;
}

// A file's text must be UTF-8: UTF-16 or UTF-32 (a byte-order mark, or NUL bytes, which no
// UTF-8 text holds) and other encodings (a byte that is not UTF-8, e.g. Latin-1's degree sign)
// are named with the line and byte, not read as a header without its columns or a cut line.
void require_utf8(const std::string& file, std::istream& in) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto starts = [&text](const char* m, std::size_t k) { return text.size() >= k && text.compare(0, k, m, k) == 0; };
  if (starts("\xFF\xFE\x00\x00", 4) || starts("\x00\x00\xFE\xFF", 4))
    throw ConfigError(file + ": is UTF-32 text (its byte-order mark): save it as UTF-8");
  if (starts("\xFF\xFE", 2) || starts("\xFE\xFF", 2))
    throw ConfigError(file + ": is UTF-16 text (its byte-order mark): save it as UTF-8");
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos) {
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    throw ConfigError(file + ":" + std::to_string(line) + ": holds NUL bytes (byte " + std::to_string(nul + 1) +
                      "): UTF-16 or binary data, not UTF-8 text: save it as UTF-8");
  }
  const std::size_t bad = invalid_utf8_at(text);
  if (bad != std::string::npos) {
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n');
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[bad]));
    throw ConfigError(file + ":" + std::to_string(line) + ": byte " + std::to_string(bad + 1) + " (" + hex +
                      ") is not UTF-8 (Latin-1 or another 8-bit encoding?): save the file as UTF-8");
  }
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}
}  // namespace

CsvTable CsvTable::read(const std::string& file, const std::vector<std::string>& columns) {
  std::vector<CsvColumn> spec;
  for (const auto& c : columns) spec.push_back({c, CsvKind::kNumber, false});
  return read_columns(file, spec);
}

namespace {
std::uint64_t g_max_csv_bytes = std::uint64_t{64} << 20;
}  // namespace

std::uint64_t max_csv_bytes() { return g_max_csv_bytes; }

void set_max_csv_bytes(std::uint64_t bytes) {
  if (bytes == 0) throw ConfigError("the CSV input limit must be > 0 bytes");
  g_max_csv_bytes = bytes;
}

CsvTable CsvTable::read_columns(const std::string& file, const std::vector<CsvColumn>& columns) {
  CsvTable t;
  t.file_ = file;
  require_regular_file(file);
  {
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    if (!ec && size > g_max_csv_bytes) {
      char b[160];
      std::snprintf(b, sizeof b, ": %.3g MB is more than the input limit of %.3g MB (rnav_diagnose --max-input-mb M raises it)",
                    static_cast<double>(size) / 1e6, static_cast<double>(g_max_csv_bytes) / 1e6);
      throw ConfigError(file + b);
    }
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file + ": cannot open");
  // its encoding first: UTF-16's last byte is a NUL, not a cut line
  require_utf8(file, in);
  in.clear();
  // A file cut while being written ends inside its last line, perhaps inside a number that
  // would still read as a (shorter) valid one: a last line without its newline is refused.
  in.seekg(0, std::ios::end);
  const std::streamoff bytes = in.tellg();
  if (bytes > 0) {
    in.seekg(bytes - 1);
    if (in.get() != '\n')
      throw ConfigError(file + ": the last line has no newline: the file may have been cut while being written "
                               "(if its last line is whole, end it with a newline)");
  }
  in.seekg(0);
  std::string line;
  if (std::getline(in, line) && line.rfind("\xEF\xBB\xBF", 0) == 0)
    throw ConfigError(file + ":1: starts with a byte-order mark (UTF-8 BOM): save the file as plain UTF-8 or ASCII");
  if (!in || trim(line).empty())
    throw ConfigError(file + ":1: missing header line (expected columns: " + [&] {
      std::string s;
      for (const auto& c : columns) s += (s.empty() ? "" : ",") + c.name + (c.optional ? "?" : "");
      return s;
    }() + ")");
  const auto header = split(line);
  // a name given twice: which column is meant is ambiguous (the reader would take one silently)
  for (std::size_t i = 0; i < header.size(); ++i)
    for (std::size_t j = i + 1; j < header.size(); ++j)
      if (!header[i].empty() && header[i] == header[j])
        throw ConfigError(file + ":1: column '" + header[i] + "' appears twice in the header (fields " + std::to_string(i + 1) +
                          " and " + std::to_string(j + 1) + "): which one holds the data is ambiguous; rename or remove one");
  std::vector<int> idx;  // field index per asked column, -1 for an absent optional one
  for (const auto& c : columns) {
    int found = -1;
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == c.name) found = static_cast<int>(i);
    if (found < 0 && !c.optional) {
      // a CSV separated by ';' (a spreadsheet's locale export) reads as one column
      if (header.size() == 1 && line.find(';') != std::string::npos)
        throw ConfigError(file + ":1: the header is separated by ';', not ',' (columns must be comma-separated: " +
                          "export the file with ',' as separator and '.' as decimal point)");
      throw ConfigError(file + ":1: header lacks column '" + c.name + "'");
    }
    idx.push_back(found);
    if (found < 0) continue;
    if (c.kind == CsvKind::kText) t.text_[c.name];
    else t.cols_[c.name];
  }
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (trim(line).empty()) {
      // Only trailing blank lines are allowed.
      std::string rest;
      while (std::getline(in, rest))
        if (!trim(rest).empty())
          throw ConfigError(file + ":" + std::to_string(lineno) + ": empty line inside the data");
      break;
    }
    const auto cells = split(line);
    if (cells.size() != header.size())
      throw ConfigError(file + ":" + std::to_string(lineno) + ": " + std::to_string(cells.size()) +
                        " fields, the header has " + std::to_string(header.size()));
    for (std::size_t k = 0; k < columns.size(); ++k) {
      if (idx[k] < 0) continue;
      const CsvColumn& c = columns[k];
      const std::string& cell = cells[static_cast<std::size_t>(idx[k])];
      const std::string where = file + ":" + std::to_string(lineno) + ": column '" + c.name +
                                "' (field " + std::to_string(idx[k] + 1) + "): ";
      if (c.kind == CsvKind::kText) {
        if (cell.empty()) throw ConfigError(where + "empty text");
        t.text_[c.name].push_back(cell);
        continue;
      }
      if (c.kind == CsvKind::kNumberOrEmpty && cell.empty()) {
        t.cols_[c.name].push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      double v = 0;
      std::string why;
      if (!parse_decimal(cell, v, why)) throw ConfigError(where + "'" + cell + "' is not a finite number (" + why + ")");
      t.cols_[c.name].push_back(v);
    }
    t.lines_.push_back(lineno);
  }
  return t;
}

const std::vector<double>& CsvTable::col(const std::string& name) const {
  const auto it = cols_.find(name);
  if (it == cols_.end()) throw std::logic_error("CsvTable: column " + name + " was not read");
  return it->second;
}

const std::vector<std::string>& CsvTable::text(const std::string& name) const {
  const auto it = text_.find(name);
  if (it == text_.end()) throw std::logic_error("CsvTable: text column " + name + " was not read");
  return it->second;
}

void CsvTable::require_time_order(const std::string& name, bool allow_equal) const {
  const auto& c = col(name);
  for (std::size_t i = 1; i < c.size(); ++i)
    if (c[i] < c[i - 1] || (!allow_equal && c[i] == c[i - 1]))
      throw ConfigError(file_ + ":" + std::to_string(lines_[i]) + ": column '" + name +
                        "' is not in time order (" + std::to_string(c[i]) + " after " +
                        std::to_string(c[i - 1]) + ")");
}

}  // namespace rnav
