// The description beside a CSV file the project writes (common/io/csv_columns.hpp), checked the way
// a user reads it: NAME.units.json exists beside NAME.csv, parses as one JSON object whose keys
// are the CSV header's columns, in the header's order, each {"unit": text, "meaning": non-empty
// text} and nothing else.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace rnav_test {

/// "" if the description beside `csv` is complete and matches its header; else what is wrong,
/// naming the file.
inline std::string csv_units_problem(const std::filesystem::path& csv) {
  const std::string c = csv.string();
  const std::string u = (c.size() > 4 && c.compare(c.size() - 4, 4, ".csv") == 0 ? c.substr(0, c.size() - 4) : c) + ".units.json";
  std::ifstream cf(csv);
  if (!cf) return c + ": cannot be read";
  std::string header;
  std::getline(cf, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string n; std::getline(hs, n, ',');) names.push_back(n);
  std::ifstream uf(u);
  if (!uf) return u + ": missing (beside " + c + ")";
  std::stringstream text;
  text << uf.rdbuf();
  nlohmann::ordered_json j;
  try {
    j = nlohmann::ordered_json::parse(text.str());
  } catch (const std::exception& e) {
    return u + ": not JSON: " + e.what();
  }
  if (!j.is_object()) return u + ": not a JSON object";
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) {
    keys.push_back(k);
    if (!v.is_object() || v.size() != 2 || !v.contains("unit") || !v.contains("meaning") || !v["unit"].is_string() ||
        !v["meaning"].is_string())
      return u + ": column " + k + ": expected {\"unit\": text, \"meaning\": text}";
    if (v["meaning"].get<std::string>().empty()) return u + ": column " + k + ": empty meaning";
  }
  if (keys != names) {
    std::string a, b;
    for (const auto& k : keys) a += (a.empty() ? "" : ",") + k;
    for (const auto& n : names) b += (b.empty() ? "" : ",") + n;
    return u + ": keys " + a + " are not the header's columns " + b + " (in order)";
  }
  return "";
}

/// Every *.csv directly in `dir` checked with csv_units_problem, and every *.units.json there has
/// its CSV: the problems, one a line ("" if none). `n_csv` (if given) receives the number of CSVs.
inline std::string csv_folder_units_problems(const std::filesystem::path& dir, int* n_csv = nullptr) {
  namespace fs = std::filesystem;
  std::string out;
  int n = 0;
  const std::string tail = ".units.json";
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".csv") {
      ++n;
      const std::string p = csv_units_problem(e.path());
      if (!p.empty()) out += p + "\n";
    } else if (name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0) {
      const fs::path csv = dir / (name.substr(0, name.size() - tail.size()) + ".csv");
      if (!fs::exists(csv)) out += e.path().string() + ": no " + csv.filename().string() + " beside it\n";
    }
  }
  if (n_csv) *n_csv = n;
  return out;
}

}  // namespace rnav_test
