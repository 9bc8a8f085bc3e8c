// Shards of one ensemble joined by merge_shards (scripts/compose/merge) give the outputs of one run of
// the whole ensemble byte for byte, for any split and any order - the property MPI ranks and
// resumable sweeps rely on - and every way shards can fail to be one ensemble is an error
// naming the culprit.
#include <catch2/catch.hpp>

#include "test/csv_units.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "scripts/compose/merge/folder_pack.hpp"
#include "scripts/compose/merge/shard_merge.hpp"
#include "test/test_support.hpp"
#include "scripts/compose/scenario/uav_scenario.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace rnav;
using rnav_test::slurp;

namespace {

const std::string kPaper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";
const std::string kUav = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/uav.json";

fs::path scratch(const std::string& name) {
  return rnav_test::fresh_dir(fs::temp_directory_path() / ("rnav_test_shard_merge_" + name));
}

// Every file of `ref` is in `got` with the same bytes, and `got` holds no other file.
void require_same_files(const fs::path& ref, const fs::path& got) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(ref)) {
    const auto name = e.path().filename().string();
    if (name.front() == '.') continue;
    INFO(name);
    REQUIRE(fs::exists(got / name));
    CHECK(slurp(e.path()) == slurp(got / name));
    ++n;
  }
  std::size_t m = 0;
  for (const auto& e : fs::directory_iterator(got)) m += e.path().filename().string().front() != '.';
  CHECK(m == n);
  CHECK(n >= 7);  // the statistics files, realizations.csv, ensemble_state.json, scenario.json
  // Every CSV of the merge has its units.json beside it (keys = its header's columns, in order).
  int n_csv = 0;
  CHECK(rnav_test::csv_folder_units_problems(got, &n_csv) == "");
  CHECK(n_csv >= 3);
  CHECK(fs::exists(got / "realizations.units.json"));
}

template <class Sc> void run(const Sc& sc, const fs::path& dir, int first, int n, std::int64_t seed) {
  const auto r = run_inproc_ensemble(sc, n, seed, dir.string(), {}, first);
  REQUIRE(r.exit_code == 0);
}

std::string merge_error(const std::vector<fs::path>& shards, const fs::path& out) {
  std::vector<std::string> s;
  for (const auto& p : shards) s.push_back(p.string());
  try {
    merge_shards(s, out.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("shards of a landing ensemble merged in any order equal one run", "[merge]") {
  const auto d = scratch("landing");
  const Scenario sc = Scenario::load(kPaper, {});
  run(sc, d / "whole", 0, 12, 5);
  // Splits of 0 ... 11 into realization ranges, given to the merge in a scrambled order.
  const std::vector<std::vector<std::pair<int, int>>> splits{{{5, 7}, {0, 5}}, {{4, 8}, {0, 1}, {1, 3}}, {{0, 12}}};
  int k = 0;
  for (const auto& split : splits) {
    std::vector<std::string> dirs;
    for (const auto& [first, n] : split) {
      const fs::path p = d / ("s" + std::to_string(k) + "_" + std::to_string(first));
      run(sc, p, first, n, 5);
      dirs.push_back(p.string());
    }
    const fs::path out = d / ("merged" + std::to_string(k++));
    const auto r = merge_shards(dirs, out.string());
    CHECK(r.kind == "landing");
    CHECK(r.realizations == 12);
    require_same_files(d / "whole", out);
  }
}

TEST_CASE("shards of a landing ensemble with the data link merged equal one run with its datalink.csv", "[merge][datalink]") {
  const auto d = scratch("landing_datalink");
  const Scenario sc = Scenario::load(kPaper, {"datalink.enabled=true", "datalink.peak_power_w=0.03"});
  run(sc, d / "whole", 0, 5, 3);
  run(sc, d / "a", 0, 2, 3);
  run(sc, d / "b", 2, 3, 3);
  merge_shards({(d / "b").string(), (d / "a").string()}, (d / "merged").string());
  require_same_files(d / "whole", d / "merged");
  const std::string rows = slurp(d / "merged" / "datalink.csv");
  CHECK(rows.rfind("realization,sent,lost\n0,997,", 0) == 0);
  CHECK(rows.find("\n4,997,") != std::string::npos);
}

TEST_CASE("shards of an azimuth-only ensemble merged in any order equal one run", "[merge]") {
  const auto d = scratch("uav");
  // The tracked realization (track.csv) lies in the middle shard.
  const UavScenario sc = UavScenario::load(kUav, {"logger.track_realization=3"});
  run(sc, d / "whole", 0, 6, 2);
  run(sc, d / "a", 0, 2, 2);
  run(sc, d / "b", 2, 3, 2);
  run(sc, d / "c", 5, 1, 2);
  CHECK(fs::exists(d / "b" / "track.csv"));
  CHECK_FALSE(fs::exists(d / "a" / "track.csv"));
  const auto r = merge_shards({(d / "c").string(), (d / "a").string(), (d / "b").string()}, (d / "m").string());
  CHECK(r.kind == "uav");
  CHECK(r.realizations == 6);
  require_same_files(d / "whole", d / "m");
}

TEST_CASE("shards run with other lock-step settings join: the runner section changes no result", "[merge]") {
  // scripts/run takes a whole landing realization as one window over LCM; one process keeps
  // 100 s. Shards of both kinds join into one run's statistics; scenario.json is realization 0's.
  const auto d = scratch("runner");
  const Scenario sc = Scenario::load(kPaper, {});
  run(sc, d / "whole", 0, 5, 4);
  run(Scenario::load(kPaper, {"runner.window_s=37", "runner.wire=sample"}), d / "a", 0, 2, 4);
  run(sc, d / "b", 2, 3, 4);
  REQUIRE(slurp(d / "a" / "scenario.json") != slurp(d / "b" / "scenario.json"));
  const auto r = merge_shards({(d / "b").string(), (d / "a").string()}, (d / "m").string());
  CHECK(r.realizations == 5);
  for (const char* f : {"table2.json", "table2_detail.json", "stats_time.csv", "stats_range.csv", "realizations.csv",
                        "ensemble_state.json"}) {
    INFO(f);
    CHECK(slurp(d / "m" / f) == slurp(d / "whole" / f));
  }
  CHECK(slurp(d / "m" / "scenario.json") == slurp(d / "a" / "scenario.json"));
}

TEST_CASE("shards that are not one ensemble are refused naming the culprit", "[merge]") {
  const auto d = scratch("bad");
  const Scenario sc = Scenario::load(kPaper, {});
  run(sc, d / "a", 0, 3, 5);
  run(sc, d / "b", 3, 3, 5);
  run(sc, d / "gap", 7, 2, 5);
  run(sc, d / "seed6", 3, 3, 6);
  run(Scenario::load(kPaper, {"radar.x_m=-1300"}), d / "other", 3, 3, 5);
  CHECK_THAT(merge_error({d / "a", d / "gap"}, d / "o1"), Catch::Contains("missing 3 ... 6"));
  CHECK_THAT(merge_error({d / "a", d / "b", d / "a"}, d / "o2"),
             Catch::Contains((d / "a").string() + "/ensemble_state.json") && Catch::Contains("realization 0 is already"));
  CHECK_THAT(merge_error({d / "a", d / "seed6"}, d / "o3"),
             Catch::Contains((d / "seed6").string()) && Catch::Contains("seed 6"));
  CHECK_THAT(merge_error({d / "a", d / "other"}, d / "o4"),
             Catch::Contains((d / "other").string() + "/scenario.json differs"));
  CHECK_THAT(merge_error({d / "a", d / "nowhere"}, d / "o5"), Catch::Contains((d / "nowhere").string()));
  CHECK_THAT(merge_error({}, d / "o6"), Catch::Contains("no shard"));
  // A damaged exact sum in a state file: named with the file and where in it.
  {
    std::string st = slurp(d / "b" / "ensemble_state.json");
    const auto at = st.find("\"sum\":[\"");
    REQUIRE(at != std::string::npos);
    st.insert(at + 8, "zz");
    std::ofstream(d / "b" / "ensemble_state.json", std::ios::binary) << st;
  }
  CHECK_THAT(merge_error({d / "a", d / "b"}, d / "o7"),
             Catch::Contains((d / "b").string() + "/ensemble_state.json") && Catch::Contains("not an exact sum"));
  // A value of the wrong type, and JSON nested beyond the parser's limit: named, no crash.
  {
    std::string st = slurp(d / "a" / "ensemble_state.json");
    const auto frames = st.find("\"by_time\":[{\"utime\":");
    REQUIRE(frames != std::string::npos);
    const auto number = frames + 20, end = st.find(',', number);
    st.replace(number, end - number, "\"x\"");  // the first utime as a string
    std::ofstream(d / "a2.json", std::ios::binary) << st;
    fs::create_directories(d / "a2");
    fs::copy_file(d / "a" / "scenario.json", d / "a2" / "scenario.json");
    fs::copy_file(d / "a" / "realizations.csv", d / "a2" / "realizations.csv");
    fs::rename(d / "a2.json", d / "a2" / "ensemble_state.json");
    CHECK_THAT(merge_error({d / "a2"}, d / "o8"), Catch::Contains((d / "a2").string() + "/ensemble_state.json"));
    std::ofstream(d / "a2" / "ensemble_state.json", std::ios::binary) << std::string(100000, '[') << std::string(100000, ']');
    CHECK_THAT(merge_error({d / "a2"}, d / "o9"), Catch::Contains("nested deeper"));
  }
  // Nothing was written by a refused merge.
  CHECK_FALSE(fs::exists(d / "o1" / "table2.json"));
}

TEST_CASE("a shard's CSV whose header is not the one this build writes is refused naming it", "[merge]") {
  // The merged file's header and units.json come from this build's column lists: rows under
  // another header would be described wrongly, so they are refused, not joined.
  const auto d = scratch("header");
  const UavScenario sc = UavScenario::load(kUav, {"logger.track_realization=1"});
  run(sc, d / "a", 0, 2, 2);
  run(sc, d / "b", 2, 2, 2);
  REQUIRE(merge_error({d / "a", d / "b"}, d / "ok") == "(no error)");
  CHECK(rnav_test::csv_folder_units_problems(d / "ok") == "");
  CHECK(slurp(d / "ok" / "track.units.json") == slurp(d / "a" / "track.units.json"));
  // A shard without units.json files (they are written from the code, not copied) still joins.
  fs::remove(d / "b" / "realizations.units.json");
  CHECK(merge_error({d / "a", d / "b"}, d / "ok2") == "(no error)");
  CHECK(slurp(d / "ok2" / "realizations.units.json") == slurp(d / "ok" / "realizations.units.json"));
  const auto edit = [&](const fs::path& f, const std::string& from, const std::string& to) {
    std::string t = slurp(f);
    const auto at = t.find(from);
    REQUIRE(at != std::string::npos);
    t.replace(at, from.size(), to);
    std::ofstream(f, std::ios::binary) << t;
  };
  edit(d / "b" / "realizations.csv", "pos_err_north_m", "pos_err_n_m");
  CHECK_THAT(merge_error({d / "a", d / "b"}, d / "o1"),
             Catch::Contains((d / "b").string() + "/realizations.csv") && Catch::Contains("header is not the one this build writes"));
  edit(d / "b" / "realizations.csv", "pos_err_n_m", "pos_err_north_m");
  edit(d / "a" / "track.csv", "rpekf_P_ne_m2", "rpekf_P_en_m2");
  CHECK_THAT(merge_error({d / "a", d / "b"}, d / "o2"),
             Catch::Contains((d / "a").string() + "/track.csv") && Catch::Contains("header is not the one"));
}

TEST_CASE("folder packs carry a shard's files between ranks and refuse damaged packs", "[merge]") {
  const auto d = scratch("pack");
  fs::create_directories(d / "src");
  std::ofstream(d / "src" / "a.csv", std::ios::binary) << "x,y\n1,2\n";
  std::ofstream(d / "src" / "empty.txt", std::ios::binary) << "";
  std::ofstream(d / "src" / "bin.dat", std::ios::binary) << std::string("\0\n7\n\xff", 5);
  std::ofstream(d / "src" / ".rnav-output", std::ios::binary) << "marker";  // hidden: not carried
  const std::string pack = pack_folder((d / "src").string());
  unpack_folder(pack, (d / "dst").string(), "test pack");
  for (const char* f : {"a.csv", "empty.txt", "bin.dat"}) {
    INFO(f);
    CHECK(slurp(d / "dst" / f) == slurp(d / "src" / f));
  }
  CHECK_FALSE(fs::exists(d / "dst" / ".rnav-output"));
  const auto bad = [&](const std::string& p) {
    try {
      unpack_folder(p, (d / "bad").string(), "rank 2 on hostx");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string head = "rnav-folder-pack 1\n";
  CHECK_THAT(bad("not a pack"), Catch::Contains("rank 2 on hostx: not a folder pack"));
  CHECK_THAT(bad(head + "../x\n1\nA"), Catch::Contains("bad file name '../x'"));
  CHECK_THAT(bad(head + "a/b\n1\nA"), Catch::Contains("bad file name 'a/b'"));
  CHECK_THAT(bad(head + "a\n99\nA"), Catch::Contains("file 'a': bad size '99'"));
  CHECK_THAT(bad(head + "a\n-1\nA"), Catch::Contains("bad size"));
  CHECK_THAT(bad(head + "a"), Catch::Contains("ends inside a file's name"));
  CHECK_FALSE(fs::exists(d / "bad" / "x"));
}
