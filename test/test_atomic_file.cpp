// Writing results: never through a planted link, never over a user's folder, every byte checked.
#include "common/io/atomic_file.hpp"
#include "common/io/config.hpp"
#include "test/test_support.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using rnav_test::slurp;

namespace {

fs::path fresh(const std::string& name) {
  return rnav_test::fresh_dir(fs::temp_directory_path() / ("rnav_test_atomic_" + name + "_" + std::to_string(::getpid())));
}

}  // namespace

TEST_CASE("atomic file: a link planted at the partial name is replaced, its target untouched", "[files]") {
  const fs::path d = fresh("link");
  const fs::path victim = d / "victim.txt";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, d / ".out.csv.partial");
  rnav::write_file_atomic(d.string(), "out.csv", "t_s\n1\n");
  CHECK(slurp(victim) == "precious");
  CHECK(slurp(d / "out.csv") == "t_s\n1\n");
  CHECK_FALSE(fs::exists(d / ".out.csv.partial"));
  fs::remove_all(d);
}

TEST_CASE("atomic file: a write that cannot complete is an error naming the file", "[files][input]") {
  const fs::path d = fresh("fail");
  // A folder where the partial file cannot be created: the error names it and the reason.
  fs::create_directories(d / ".out.csv.partial" / "x");  // a non-empty folder in the way
  CHECK_THROWS_WITH(rnav::write_file_atomic(d.string(), "out.csv", "abc"),
                    Catch::Contains(".out.csv.partial") && Catch::Contains("cannot"));
  CHECK_THROWS_WITH(rnav::write_file_atomic((d / "missing_dir").string(), "out.csv", "abc"),
                    Catch::Contains("missing_dir/.out.csv.partial") && Catch::Contains("No such file"));
  fs::remove_all(d);
}

TEST_CASE("atomic file in pieces: nothing at the final name until commit, abandoned pieces removed", "[files]") {
  const fs::path d = fresh("pieces");
  std::ofstream(d / "rows.csv") << "an earlier result";
  {
    rnav::AtomicFileWriter w(d.string(), "rows.csv");
    w.append("a,b\n");
    w.append("1,2\n");
    CHECK(slurp(d / "rows.csv") == "an earlier result");  // untouched until commit
    CHECK(slurp(d / ".rows.csv.partial") == "a,b\n1,2\n");
    w.commit();
    CHECK_THROWS(w.append("3,4\n"));
  }
  CHECK(slurp(d / "rows.csv") == "a,b\n1,2\n");
  CHECK_FALSE(fs::exists(d / ".rows.csv.partial"));
  {
    rnav::AtomicFileWriter w(d.string(), "rows.csv");
    w.append("half");
  }  // destroyed without commit (a failed run): the partial file goes, the result stays
  CHECK_FALSE(fs::exists(d / ".rows.csv.partial"));
  CHECK(slurp(d / "rows.csv") == "a,b\n1,2\n");
  fs::remove_all(d);
}

TEST_CASE("output folder: a foreign non-empty folder is refused and left intact, --force and earlier outputs pass",
          "[files][input]") {
  const fs::path d = fresh("outdir");
  const fs::path mine = d / "mine";
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.txt") << "precious";
  CHECK_THROWS_WITH(rnav::prepare_output_dir(mine.string(), false),
                    Catch::Contains(mine.string()) && Catch::Contains("thesis.txt") && Catch::Contains("--force"));
  CHECK(slurp(mine / "thesis.txt") == "precious");
  CHECK_FALSE(fs::exists(mine / rnav::kOutputMarker));
  // A new folder is created and marked; marked, it is accepted again.
  rnav::prepare_output_dir((d / "new").string(), false);
  CHECK(fs::exists(d / "new" / rnav::kOutputMarker));
  std::ofstream(d / "new" / "radar.csv") << "t_s\n";
  CHECK_NOTHROW(rnav::prepare_output_dir((d / "new").string(), false));
  // An empty folder is fine; a file in the way is not; --force writes into the foreign one.
  fs::create_directories(d / "empty");
  CHECK_NOTHROW(rnav::prepare_output_dir((d / "empty").string(), false));
  std::ofstream(d / "afile") << "x";
  CHECK_THROWS_WITH(rnav::prepare_output_dir((d / "afile").string(), false), Catch::Contains("not a folder"));
  CHECK_NOTHROW(rnav::prepare_output_dir(mine.string(), true));
  CHECK(slurp(mine / "thesis.txt") == "precious");
  fs::remove_all(d);
}
