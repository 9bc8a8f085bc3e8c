// The column descriptions of the CSV files the project writes (common/io/csv_columns.hpp): one list
// gives the header and NAME.units.json, keys in the header's order; a bad list is refused naming
// the column.
#include "test/shell.hpp"
#include "common/io/csv_columns.hpp"

#include "test/csv_units.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>


#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;
using rnav::CsvColumnDoc;

namespace {

// The message of the std::invalid_argument the list raises in every use, the same in each.
std::string refusal(const std::vector<CsvColumnDoc>& c) {
  std::string msg[3];
  try {
    rnav::check_csv_columns(c);
  } catch (const std::invalid_argument& e) {
    msg[0] = e.what();
  }
  try {
    rnav::csv_header(c);
  } catch (const std::invalid_argument& e) {
    msg[1] = e.what();
  }
  try {
    rnav::csv_units_json(c);
  } catch (const std::invalid_argument& e) {
    msg[2] = e.what();
  }
  CHECK(msg[1] == msg[0]);
  CHECK(msg[2] == msg[0]);
  return msg[0].empty() ? "(accepted)" : msg[0];
}

const std::vector<CsvColumnDoc> kExample{{"t_s", "s", "time since the flight's start"}, {"n", "", "realizations averaged"}};

}  // namespace

TEST_CASE("csv columns: the header and units.json of one list, in the header's order", "[csv]") {
  CHECK(rnav::csv_header(kExample) == "t_s,n\n");
  CHECK(rnav::csv_units_json(kExample) ==
        "{\n"
        " \"t_s\": {\"unit\": \"s\", \"meaning\": \"time since the flight's start\"},\n"
        " \"n\": {\"unit\": \"\", \"meaning\": \"realizations averaged\"}\n"
        "}\n");
  // Keys in the list's order, not sorted (nlohmann::json would sort them: z_m before a_m here).
  const std::vector<CsvColumnDoc> c{{"z_m", "m", "lateral"}, {"a_m", "m", "along"}, {"M", "", "count"}, {"_k", "", "index"}};
  const auto j = nlohmann::ordered_json::parse(rnav::csv_units_json(c));
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  CHECK(keys == std::vector<std::string>{"z_m", "a_m", "M", "_k"});
  CHECK(keys == rnav::csv_header_names(rnav::csv_header(c)));
  CHECK(j["z_m"]["unit"] == "m");
  CHECK(j["M"]["unit"] == "");
  CHECK(j["_k"]["meaning"] == "index");
  // Text that JSON must escape survives the round trip.
  const std::vector<CsvColumnDoc> q{{"x", "m^2", "a \"quoted\" \\ back\\slash, a tab\there and a d\xc3\xa9j\xc3\xa0 vu"}};
  CHECK(nlohmann::json::parse(rnav::csv_units_json(q))["x"]["meaning"] == q[0].meaning);
  CHECK(rnav::csv_header_names("a,b_m,c\r\nrest") == std::vector<std::string>{"a", "b_m", "c"});
}

TEST_CASE("csv columns: a name that is not plain, given twice, or without a meaning is refused naming it", "[csv]") {
  for (const char* bad : {"1a", "a-b", "a b", "range[m]", "", "t_s ", "h\xc3\xa9"}) {
    INFO("name '" << bad << "'");
    CHECK_THAT(refusal({{"t_s", "s", "time"}, {bad, "m", "something"}}),
               Catch::Contains(std::string("column 2 '") + bad + "'") && Catch::Contains("not a plain name"));
  }
  CHECK_THAT(refusal({{"t_s", "s", "time"}, {"n", "", "count"}, {"t_s", "s", "again"}}),
             Catch::Contains("column 3 't_s'") && Catch::Contains("given twice"));
  CHECK_THAT(refusal({{"t_s", "s", "time"}, {"range_m", "m", ""}}), Catch::Contains("column 2 'range_m'") && Catch::Contains("no meaning"));
  CHECK_THAT(refusal({{"range_m", "m", " \t"}}), Catch::Contains("column 1 'range_m'") && Catch::Contains("no meaning"));
  CHECK_THAT(refusal({}), Catch::Contains("at least one column"));
  CHECK(refusal(kExample) == "(accepted)");
  CHECK(refusal({{"a", "", "x"}, {"A", "", "y"}, {"a1_", "", "z"}}) == "(accepted)");  // names are case-sensitive
}

TEST_CASE("csv columns: units.json is written beside the CSV, atomically", "[csv][files]") {
  const fs::path d = rnav_test::scratch("csv_columns_write");
  CHECK(rnav::csv_units_name("stats_time.csv") == "stats_time.units.json");
  CHECK(rnav::csv_units_name("out/a.b.csv") == "out/a.b.units.json");
  CHECK(rnav::csv_units_name("table") == "table.units.json");
  std::ofstream(d / "x.csv") << rnav::csv_header(kExample) << "1.5,2\n";
  rnav::write_csv_units(d.string(), "x.csv", kExample);
  CHECK(rnav_test::slurp(d / "x.units.json") == rnav::csv_units_json(kExample));
  CHECK(rnav_test::csv_units_problem(d / "x.csv").empty());
  CHECK_FALSE(fs::exists(d / ".x.units.json.partial"));
  // The path form, and the test's own check can fail: a header that no longer matches is named.
  std::ofstream(d / "y.csv") << "n,t_s\n2,1.5\n";
  rnav::write_csv_units((d / "y.csv").string(), kExample);
  CHECK(fs::exists(d / "y.units.json"));
  CHECK_THAT(rnav_test::csv_units_problem(d / "y.csv"), Catch::Contains("not the header's columns n,t_s"));
  std::ofstream(d / "z.csv") << "t_s,n\n";
  CHECK_THAT(rnav_test::csv_units_problem(d / "z.csv"), Catch::Contains("z.units.json: missing"));
  int n = 0;
  const std::string all = rnav_test::csv_folder_units_problems(d, &n);
  CHECK(n == 3);
  CHECK_THAT(all, Catch::Contains("y.units.json") && Catch::Contains("z.units.json") && !Catch::Contains("x.units.json"));
  // A list refused writes nothing.
  CHECK_THROWS_AS(rnav::write_csv_units(d.string(), "w.csv", {{"bad name", "", "x"}}), std::invalid_argument);
  CHECK_FALSE(fs::exists(d / "w.units.json"));
  fs::remove_all(d);
}

TEST_CASE("csv columns: the geodetic track's columns", "[csv]") {
  const auto c = rnav::geo_track_columns("time of validity", "the navigation solution's");
  CHECK(rnav::csv_header(c) == "t_s,lat_deg,lon_deg,h_m\n");
  CHECK(c[0].unit == "s");
  CHECK(c[1].unit == "deg");
  CHECK(c[3].unit == "m");
  CHECK(c[3].meaning.find("WGS84 ellipsoid") != std::string::npos);
  CHECK(c[1].meaning.find("the navigation solution's position") != std::string::npos);
  CHECK(rnav::csv_header(rnav::geo_track_columns("t", "the object's true", false)) == "t_s,lat_deg,lon_deg\n");
}
