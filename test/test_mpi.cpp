// scripts/run --ranks K: an ensemble sharded over MPI ranks (rnav_mpi under mpirun) gives the
// same bytes as one run of the whole ensemble for any K, in-process or with every process
// separate over LCM per rank; a rank that dies fails the run naming its rank, host and
// realization range.
#include <catch2/catch.hpp>

#include "test/shell.hpp"

#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using rnav_test::scratch;
using rnav_test::sh;
using rnav_test::slurp;

namespace {

const std::string kRun = std::string(RNAV_SOURCE_DIR) + "/scripts/run ";

void require_same(const fs::path& a, const fs::path& b, const std::vector<std::string>& files) {
  for (const auto& f : files) {
    INFO(f << ": " << a << " vs " << b);
    REQUIRE(fs::exists(a / f));
    REQUIRE(fs::exists(b / f));
    CHECK(slurp(a / f) == slurp(b / f));
  }
}

const std::vector<std::string> kLanding{"table2.json", "table2_detail.json", "table2.txt", "stats_time.csv",
                                        "stats_range.csv", "realizations.csv", "ensemble_state.json", "scenario.json"};

}  // namespace

TEST_CASE("MPI ranks: 1 and 3 ranks give one process's bytes", "[mpi]") {
  const auto d = scratch("mpi_ranks");
  const std::string args = "paper --inproc --no-plots --realizations 25 --seed 7 --out ";
  const auto one = sh(kRun + args + (d / "one").string());
  REQUIRE(one.status == 0);
  for (int k : {1, 3}) {
    const auto out = d / ("ranks" + std::to_string(k));
    const auto r = sh(kRun + args + out.string() + " --ranks " + std::to_string(k));
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.output, Catch::Contains(std::to_string(k) + " ranks, 25 realizations (inproc)"));
    require_same(d / "one", out, kLanding);
  }
}

TEST_CASE("MPI ranks over LCM: every process separate in each rank, the same bytes", "[mpi]") {
  const auto d = scratch("mpi_lcm");
  // One multi-process run: its scenario.json names the same lock-step window as each rank's.
  const auto one = sh(kRun + "paper --no-plots --realizations 6 --seed 3 --out " + (d / "one").string());
  REQUIRE(one.status == 0);
  const auto r = sh(kRun + "paper --no-plots --realizations 6 --seed 3 --ranks 2 --out " + (d / "lcm").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("2 ranks, 6 realizations (lcm)"));
  require_same(d / "one", d / "lcm", kLanding);
}

TEST_CASE("MPI ranks: azimuth-only ensemble with its track in a middle rank", "[mpi]") {
  const auto d = scratch("mpi_uav");
  const std::string args = "uav --inproc --no-plots --realizations 6 --seed 2 --set logger.track_realization=3 --out ";
  REQUIRE(sh(kRun + args + (d / "one").string()).status == 0);
  const auto r = sh(kRun + args + (d / "k3").string() + " --ranks 3");
  INFO(r.output);
  REQUIRE(r.status == 0);
  require_same(d / "one", d / "k3",
               {"summary.json", "summary.txt", "uav_stats_time.csv", "realizations.csv", "track.csv", "ensemble_state.json"});
}

TEST_CASE("MPI ranks: a rank killed outright fails the run naming rank host and realizations", "[mpi]") {
  const auto d = scratch("mpi_die");
  char host[256] = {0};
  gethostname(host, sizeof host - 1);
  // Rank 1 of 3 over 25 realizations runs floor(25/3) = 8 ... floor(50/3) - 1 = 15.
  const auto r = sh("RNAV_MPI_DIE_RANK=1 " + kRun + "paper --inproc --no-plots --realizations 25 --ranks 3 --out " +
                    (d / "out").string());
  INFO(r.output);
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Catch::Contains("MPI rank 1 on " + std::string(host) + " (realizations 8 ... 15) was killed by signal 9"));
  CHECK_FALSE(fs::exists(d / "out"));
  CHECK_FALSE(fs::exists(d / "out.failed" / "table2.json"));
}

TEST_CASE("MPI ranks: bad --ranks and conflicting options are refused", "[mpi]") {
  const auto d = scratch("mpi_bad");
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"--ranks 0", "--ranks must be an integer in [1, 1024], got '0'"},
           {"--ranks x", "--ranks must be an integer in [1, 1024], got 'x'"},
           {"--ranks 2 --first-realization 3", "--ranks runs the whole ensemble"},
           {"--ranks 2 --realtime", "--ranks does not work with --realtime"}}) {
    const auto r = sh(kRun + "paper --no-plots --realizations 4 " + args + " --out " + (d / "out").string());
    INFO(args << "\n" << r.output);
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Catch::Contains(message));
  }
}

TEST_CASE("false_alarm_study --ranks: the same flights and verdicts as one process", "[mpi]") {
  // 5 flights over 2 ranks (flights 0-1 and 2-4): every line but the timing and the progress
  // lines (their order and times depend on the scheduling) is the same.
  const std::string fa = std::string(RNAV_SOURCE_DIR) + "/scripts/false_alarm_study 5 7000";
  const std::string results = " 2>&1 | grep -v -e '^time: ' -e '^false_alarm_study: '";
  const auto one = sh(fa + results);
  const auto two = sh(fa + " --ranks 2" + results);
  INFO(one.output << "\n---\n" << two.output);
  REQUIRE(one.status == 0);
  REQUIRE(two.status == 0);
  CHECK_THAT(one.output, Catch::Contains("flights=5 "));
  CHECK(one.output == two.output);
}
