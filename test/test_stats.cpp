// Unit tests of loggers/prl_stats.hpp: running moments, Table 2 ensemble statistics and the
// files written.
#include "loggers/prl_stats.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "common/physics/random.hpp"

#include "test/csv_units.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

using rnav::Moments;
using rnav::PlotErrors;
using rnav::PrlStats;
using rnav::Scenario;

namespace {

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "rnav_test_stats_XXXXXX").string();
    path = mkdtemp(tmpl.data());
  }
  ~TempDir() { std::filesystem::remove_all(path); }
};

// Table ranges (PlotErrors::range_table_m) of the plots of every synthetic realization. With
// the default table (25000 m and 4000 m, half-width 250 m): 25200, 24900 and 24750 (the
// boundary) are in the 25 km bin, 25300 is not; 4100, 3800 and 4250 (boundary) are in the
// 4 km bin, 3700 is not. The slant range from the radar (range_true_m) is set to something
// else (+ kSlantOffset) so that the test sees which of the two the Table 2 bins use.
const std::vector<double> kRanges{25300, 25200, 24900, 24750, 10000, 4250, 4100, 3800, 3700};
constexpr double kSlantOffset = 1234.0;

std::vector<PlotErrors> realization(int r, std::int64_t epoch) {
  rnav::Rng rng(31, r, rnav::Stream::kTest);
  std::vector<PlotErrors> v;
  for (std::size_t k = 0; k < kRanges.size(); ++k) {
    PlotErrors p;
    p.utime = epoch + static_cast<std::int64_t>(k) * 1000000;
    p.range_table_m = kRanges[k];
    p.range_true_m = kRanges[k] + kSlantOffset;
    for (int c = 0; c < 3; ++c) {
      p.apoi[c] = 5.0 * (c + 1) + 10 * rng.normal();
      p.toi[c] = 0.5 * c + rng.normal();
      p.bias_err[c] = 0.01 * rng.normal();
      p.bias_var[c] = 1e-4 * (1 + k);
    }
    v.push_back(p);
  }
  return v;
}

}  // namespace

TEST_CASE("Moments: mean, rms and sample sd of a small sample", "[stats]") {
  Moments<2> m;
  CHECK(m.mean(0) == 0);
  CHECK(m.rms(0) == 0);
  CHECK(m.sd(0) == 0);
  m.add({1.0, -3.0});
  CHECK(m.sd(0) == 0);  // n = 1
  m.add({2.0, 0.0});
  m.add({4.0, 3.0});
  // component 0: {1, 2, 4}: mean 7/3, rms sqrt(21/3), sd^2 = (16/9 + 1/9 + 25/9) / 2 = 7/3
  CHECK(m.mean(0) == Approx(7.0 / 3).epsilon(1e-15));
  CHECK(m.rms(0) == Approx(std::sqrt(7.0)).epsilon(1e-15));
  CHECK(m.sd(0) == Approx(std::sqrt(7.0 / 3)).epsilon(1e-14));
  // component 1: {-3, 0, 3}: mean 0, rms sqrt(6), sd 3
  CHECK(m.mean(1) == Approx(0.0).margin(1e-15));
  CHECK(m.rms(1) == Approx(std::sqrt(6.0)).epsilon(1e-15));
  CHECK(m.sd(1) == Approx(3.0).epsilon(1e-14));
  // constant sample: sd 0, never NaN
  Moments<1> c;
  for (int i = 0; i < 5; ++i) c.add({0.1});
  CHECK(c.sd(0) == Approx(0.0).margin(1e-8));
  CHECK_FALSE(std::isnan(c.sd(0)));
}

TEST_CASE("PaperTable2 holds the paper's Table 2 (docs/method.md)", "[stats]") {
  CHECK(rnav::PaperTable2::has(25000));
  CHECK(rnav::PaperTable2::has(4000));
  CHECK_FALSE(rnav::PaperTable2::has(10000));
  CHECK(rnav::PaperTable2::apoi(25000) == std::array<double, 3>{4.62, 45.12, 67.79});
  CHECK(rnav::PaperTable2::toi(25000) == std::array<double, 3>{3.71, 37.23, 54.81});
  CHECK(rnav::PaperTable2::apoi(4000) == std::array<double, 3>{5.39, 7.64, 12.94});
  CHECK(rnav::PaperTable2::toi(4000) == std::array<double, 3>{0.04, 0.08, -0.07});
  CHECK_THROWS_AS(rnav::PaperTable2::apoi(10000), std::invalid_argument);
}

TEST_CASE("PrlStats: Table 2 = ensemble mean of per-realization bin means and table2.json", "[stats]") {
  const Scenario sc = Scenario::from_json(nlohmann::json::object());
  const std::int64_t epoch = sc.runner.epoch_utime;
  PrlStats st(sc.logger, sc.site());
  const int R = 5;
  std::vector<std::vector<PlotErrors>> reals;
  for (int r = 0; r < R; ++r) {
    reals.push_back(realization(r, epoch));
    st.add_realization(reals.back());
  }
  CHECK(st.realizations() == R);

  // Independent computation of the table.
  const std::vector<double> table{25000, 4000};
  REQUIRE(sc.logger.table_ranges_m == table);
  std::array<std::array<double, 3>, 2> exp_apoi{}, exp_toi{};
  std::array<std::array<std::vector<double>, 3>, 2> per_real_apoi;
  for (std::size_t i = 0; i < table.size(); ++i) {
    for (const auto& real : reals) {
      std::array<double, 3> sa{}, stoi{};
      int n = 0;
      for (const auto& p : real)
        if (std::abs(p.range_table_m - table[i]) <= 250) {
          ++n;
          for (int c = 0; c < 3; ++c) sa[c] += p.apoi[c], stoi[c] += p.toi[c];
        }
      REQUIRE(n == 3);  // see kRanges
      for (int c = 0; c < 3; ++c) {
        exp_apoi[i][c] += sa[c] / n / R;
        exp_toi[i][c] += stoi[c] / n / R;
        per_real_apoi[i][c].push_back(sa[c] / n);
      }
    }
  }
  for (std::size_t i = 0; i < table.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      INFO("table range " << table[i] << " component " << c);
      CHECK(st.table_apoi()[i].n == R);
      CHECK(st.table_apoi()[i].mean(c) == Approx(exp_apoi[i][c]).epsilon(1e-12));
      CHECK(st.table_toi()[i].mean(c) == Approx(exp_toi[i][c]).epsilon(1e-12));
      // spread across realizations (for the standard error): sample sd of the bin means
      double ss = 0;
      for (double x : per_real_apoi[i][c]) ss += (x - exp_apoi[i][c]) * (x - exp_apoi[i][c]);
      CHECK(st.table_apoi()[i].sd(c) == Approx(std::sqrt(ss / (R - 1))).epsilon(1e-9));
    }

  // Per plot time: the ensemble mean over realizations.
  REQUIRE(st.by_time().size() == kRanges.size());
  for (std::size_t k = 0; k < kRanges.size(); ++k) {
    const auto& tb = st.by_time().at(epoch + static_cast<std::int64_t>(k) * 1000000);
    CHECK(tb.range_true_m == kRanges[k] + kSlantOffset);
    CHECK(tb.apoi.n == R);
    double m = 0;
    for (const auto& real : reals) m += real[k].toi[1] / R;
    CHECK(tb.toi.mean(1) == Approx(m).epsilon(1e-12));
  }

  TempDir dir;
  st.write(dir.path.string(), 42);
  std::ifstream f(dir.path / "table2.json");
  REQUIRE(f);
  const nlohmann::json j = nlohmann::json::parse(f);
  CHECK(j.at("realizations").get<long>() == R);
  CHECK(j.at("seed").get<long>() == 42);
  for (const char* row : {"APOI", "TOI"}) {
    REQUIRE(j.contains(row));
    for (std::size_t i = 0; i < table.size(); ++i) {
      const std::string key = i == 0 ? "25000" : "4000";
      REQUIRE(j[row].contains(key));
      const auto& arr = j[row][key];
      REQUIRE(arr.size() == 3);
      for (int c = 0; c < 3; ++c) {
        const double e = std::string(row) == "APOI" ? exp_apoi[i][c] : exp_toi[i][c];
        CHECK(arr[c].get<double>() == Approx(e).epsilon(1e-12));
      }
    }
  }
  for (const char* name : {"table2_detail.json", "table2.txt", "stats_time.csv", "stats_range.csv"})
    CHECK(std::filesystem::exists(dir.path / name));
  // stats_time.csv: a header and one row per plot time
  std::ifstream csv(dir.path / "stats_time.csv");
  int lines = 0;
  for (std::string l; std::getline(csv, l);) ++lines;
  CHECK(lines == 1 + static_cast<int>(kRanges.size()));
  // stats_range.csv: a header and one row per occupied range_bin_m bin of the slant range
  std::set<long> bins;
  for (double r : kRanges) bins.insert(static_cast<long>(std::floor((r + kSlantOffset) / sc.logger.range_bin_m)));
  std::ifstream rcsv(dir.path / "stats_range.csv");
  int rlines = 0;
  for (std::string l; std::getline(rcsv, l);) ++rlines;
  CHECK(rlines == 1 + static_cast<int>(bins.size()));
  // every CSV (stats_time, stats_range, realizations) has its units.json, keys = the header's columns
  int n_csv = 0;
  CHECK(rnav_test::csv_folder_units_problems(dir.path, &n_csv) == "");
  CHECK(n_csv == 3);
  {
    std::ifstream u(dir.path / "stats_time.units.json");
    const auto units = nlohmann::json::parse(u);
    CHECK(units["apoi_mean_z_m"]["unit"] == "m");
    CHECK(units["biaserr_rms_course_deg"]["unit"] == "deg");
    CHECK(units["n"]["unit"] == "");
    CHECK(units["aircraft_y_m"]["meaning"].get<std::string>().find("up") != std::string::npos);
  }
  // no temporary files left behind
  for (const auto& e : std::filesystem::directory_iterator(dir.path))
    CHECK(e.path().filename().string().find(".partial") == std::string::npos);
}

TEST_CASE("PrlStats rejects realizations without plots in a table bin or with differing counts",
          "[stats]") {
  const Scenario sc = Scenario::from_json(nlohmann::json::object());
  const std::int64_t epoch = sc.runner.epoch_utime;
  {
    PrlStats st(sc.logger, sc.site());
    auto r = realization(0, epoch);
    std::vector<PlotErrors> no4k;
    for (const auto& p : r)
      if (p.range_table_m > 5000) no4k.push_back(p);
    CHECK_THROWS_AS(st.add_realization(no4k), std::runtime_error);
  }
  {
    PrlStats st(sc.logger, sc.site());
    st.add_realization(realization(0, epoch));
    auto r = realization(1, epoch);
    r.pop_back();  // 3700 m: outside every bin -- still fine
    CHECK_NOTHROW(st.add_realization(r));
    r.pop_back();  // 3800 m: one plot fewer in the 4 km bin
    CHECK_THROWS_AS(st.add_realization(r), std::runtime_error);
  }
  {
    PrlStats st(sc.logger, sc.site());
    TempDir dir;
    CHECK_THROWS_AS(st.write(dir.path.string(), 1), std::runtime_error);  // nothing to write
  }
}
