// Integration tests: the real processes over real LCM (scripts/run puts them in a private
// network namespace, so no packet leaves the machine), the single-process ensemble, and the
// failure paths: a lost message, a killed process, bad input.
#include <catch2/catch.hpp>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "test/shell.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <algorithm>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;
using rnav_test::Result;
using rnav_test::scratch;
using rnav_test::sh;
using rnav_test::slurp;

namespace {

const std::string kRoot = RNAV_SOURCE_DIR;
const std::string kBuild = RNAV_BINARY_DIR;
const std::string kData = RNAV_DATA_DIR;  // the real recordings in the repository (test/data)

// The pid of process `name` of the run whose work folder is scratch folder d's "out.partial.*"
// (from its logs/pids file; other tests may run their own processes of the same name); 0 if it
// does not appear within 10 s.
pid_t pid_in_run(const fs::path& d, const std::string& name) {
  for (int i = 0; i < 200; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (const auto& e : fs::directory_iterator(d)) {
      const auto pids = e.path() / "logs" / "pids";
      if (e.path().filename().string().rfind("out.partial.", 0) != 0 || !fs::exists(pids)) continue;
      std::ifstream f(pids);
      std::string n;
      int pid;
      while (f >> n >> pid)
        if (n == name) return pid;
    }
  }
  return 0;
}

// Running or stopped, not a zombie: a dead orphan stays a zombie until its new parent (init, or
// a subreaper such as the test driver) reaps it.
bool alive(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(f, stat)) return false;
  const auto close = stat.rfind(')');  // "pid (comm) S ...": the state follows the command name
  return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] != 'Z' && stat[close + 2] != 'X';
}

const std::string kRun = kRoot + "/scripts/run paper --no-plots --net netns ";
// Small, fast settings for failure-path tests: wall timeouts short, few realizations; windows of
// 100 s (scripts/run would take a whole realization as one window), so --drop can name window 3.
const std::string kFast = " --set runner.stall_timeout_s=0.5 --set runner.ack_timeout_s=2 --set runner.window_s=100 ";

}  // namespace

TEST_CASE("multi-process run over LCM writes table2.json with the documented shape", "[integration]") {
  const fs::path d = scratch("mp");
  const auto r = sh(kRun + "--realizations 8 --seed 11 --out " + (d / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(slurp(d / "out" / "table2.json"));
  CHECK(j["realizations"] == 8);
  CHECK(j["seed"] == 11);
  for (const char* row : {"APOI", "TOI"})
    for (const char* range : {"25000", "4000"}) {
      REQUIRE(j[row][range].size() == 3);
      for (const auto& v : j[row][range]) CHECK(std::isfinite(v.get<double>()));
    }
  // Every process logged its options at start-up and finished cleanly.
  for (const char* n : {"trajectory", "snsins", "prl", "prl_bias", "logger"}) {
    const std::string log = slurp(d / "out" / "logs" / (std::string(n) + ".log"));
    CHECK(log.find("\"prl\"") != std::string::npos);
    CHECK(log.find("finished") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(d / "out.failed"));
}

TEST_CASE("scenario.json in the output repeats the run: every default filled in, the overrides applied",
          "[integration][determinism]") {
  const fs::path d = scratch("scenario_json");
  // In one process with overrides, then from the written file over LCM without them.
  const auto a = sh(kRun + "--realizations 4 --seed 9 --inproc --set radar.x_m=-1000 --set prl_effects.range_gain=0.001 --out " +
                    (d / "a").string());
  INFO(a.output);
  REQUIRE(a.status == 0);
  const auto sc = nlohmann::json::parse(slurp(d / "a" / "scenario.json"));
  CHECK(sc["radar"]["x_m"] == -1000.0);
  CHECK(sc["prl_effects"]["range_gain"] == 0.001);
  CHECK(sc["runner"]["wire"] == "batch");  // a default the paper file does not name
  const auto b = sh(std::string(RNAV_SOURCE_DIR) + "/scripts/run " + (d / "a" / "scenario.json").string() + " --no-plots --net netns" +
                    " --realizations 4 --seed 9 --out " + (d / "b").string());
  INFO(b.output);
  REQUIRE(b.status == 0);
  for (const char* f : {"scenario.json", "table2.json", "table2_detail.json", "stats_time.csv", "stats_range.csv", "realizations.csv"})
    CHECK(slurp(d / "a" / f) == slurp(d / "b" / f));
  // realizations.csv: Table 2's means are the ensemble means of its "table" rows (the same sums
  // in the same order, so equal to within one rounding: 1e-12 relative).
  {
    std::istringstream rows(slurp(d / "b" / "realizations.csv"));
    std::string line;
    std::getline(rows, line);
    REQUIRE(line.rfind("realization,bin,lo_m,hi_m,plots,apoi_x_m", 0) == 0);
    std::map<std::string, std::array<double, 3>> sum;  // lo_m -> APOI X Z Y
    std::map<std::string, int> n;
    while (std::getline(rows, line)) {
      std::vector<std::string> c;
      std::istringstream ls(line);
      for (std::string x; std::getline(ls, x, ',');) c.push_back(x);
      REQUIRE(c.size() == 14);
      if (c[1] != "table") continue;
      for (int k = 0; k < 3; ++k) sum[c[2]][k] += std::stod(c[5 + k]);
      ++n[c[2]];
    }
    const auto t2 = nlohmann::json::parse(slurp(d / "b" / "table2.json"));
    for (const auto& [lo, range] : std::vector<std::pair<std::string, std::string>>{{"24750", "25000"}, {"3750", "4000"}}) {
      REQUIRE(n[lo] == 4);
      for (int k = 0; k < 3; ++k) {
        const double expected = t2["APOI"][range][k].get<double>();
        CHECK(std::abs(sum[lo][k] / 4 - expected) <= 1e-12 * std::max(1.0, std::abs(expected)));
      }
    }
  }
  // Without the overrides the results differ: the file carried them.
  const auto c = sh(kRun + "--realizations 4 --seed 9 --inproc --out " + (d / "c").string());
  REQUIRE(c.status == 0);
  CHECK(slurp(d / "a" / "table2.json") != slurp(d / "c" / "table2.json"));
}

TEST_CASE("same seed: byte-identical statistics across processes, batching and transport",
          "[integration][determinism]") {
  const fs::path d = scratch("det");
  const std::string common = "--realizations 12 --seed 5 ";
  const auto a = sh(kRun + common + "--out " + (d / "a").string());
  const auto b = sh(kRun + common + "--set runner.window_s=37 --out " + (d / "b").string());
  const auto c = sh(kRun + common + "--inproc --set runner.window_s=0.25 --out " + (d / "c").string());
  const auto other = sh(kRun + "--realizations 12 --seed 6 --inproc --out " + (d / "s6").string());
  INFO(a.output << b.output << c.output);
  REQUIRE(a.status == 0);
  REQUIRE(b.status == 0);
  REQUIRE(c.status == 0);
  REQUIRE(other.status == 0);
  for (const char* f : {"table2.json", "table2_detail.json", "stats_time.csv", "stats_range.csv", "realizations.csv"}) {
    INFO(f);
    const std::string ref = slurp(d / "a" / f);
    REQUIRE(ref.size() > 100);
    CHECK(slurp(d / "b" / f) == ref);  // another lock-step window (batch) size
    CHECK(slurp(d / "c" / f) == ref);  // one process, no LCM, one truth step per window
  }
  // ... and a different seed does change them (the comparison above can fail).
  CHECK(slurp(d / "s6" / "stats_time.csv") != slurp(d / "a" / "stats_time.csv"));
}

TEST_CASE("data link enabled: the lossy link over LCM equals one process byte for byte",
          "[integration][determinism][datalink]") {
  // 0.03 W peak: the link loses about half the nav messages of the approach (its 50 % range is
  // about 16 km), so the estimator works on what survives. Over LCM with whole-realization
  // windows, over LCM with 100 s windows and a NAV_SOLUTION batch of the datalink node lost
  // (the realization is repeated and must draw the same losses), and in one process.
  const fs::path d = scratch("datalink");
  const std::string common = "--realizations 5 --seed 5 --set datalink.enabled=true --set datalink.peak_power_w=0.03 ";
  const auto a = sh(kRun + common + "--out " + (d / "a").string());
  const auto b = sh(kRun + common + kFast + "--drop datalink:NAV_SOLUTION:1:0:0 --out " + (d / "b").string());
  const auto c = sh(kRun + common + "--inproc --out " + (d / "c").string());
  const auto off = sh(kRun + "--realizations 5 --seed 5 --inproc --out " + (d / "off").string());
  INFO(a.output << b.output << c.output << off.output);
  REQUIRE(a.status == 0);
  REQUIRE(b.status == 0);
  REQUIRE(c.status == 0);
  REQUIRE(off.status == 0);
  const auto ev = nlohmann::json::parse(slurp(d / "b" / "run_events.json"));
  REQUIRE(ev["retries"].size() == 1);
  CHECK(ev["retries"][0]["realization"] == 1);
  for (const char* f : {"table2.json", "table2_detail.json", "stats_time.csv", "stats_range.csv", "realizations.csv",
                        "datalink.csv"}) {
    INFO(f);
    const std::string ref = slurp(d / "a" / f);
    REQUIRE(ref.size() > 50);
    CHECK(slurp(d / "b" / f) == ref);
    CHECK(slurp(d / "c" / f) == ref);
  }
  CHECK(nlohmann::json::parse(slurp(d / "a" / "scenario.json"))["datalink"]["peak_power_w"] == 0.03);
  // Every realization lost messages, and the lossy link changed the estimates (the comparison can fail).
  std::istringstream rows(slurp(d / "a" / "datalink.csv"));
  std::string line;
  std::getline(rows, line);
  CHECK(line == "realization,sent,lost");
  int n = 0;
  while (std::getline(rows, line)) {
    int r = -1;
    long sent = 0, lost = 0;
    REQUIRE(std::sscanf(line.c_str(), "%d,%ld,%ld", &r, &sent, &lost) == 3);
    CHECK(r == n++);
    CHECK(sent == 997);
    CHECK(lost > 200);
    CHECK(lost < sent);
  }
  CHECK(n == 5);
  CHECK(slurp(d / "off" / "stats_time.csv") != slurp(d / "a" / "stats_time.csv"));
  CHECK_FALSE(fs::exists(d / "off" / "datalink.csv"));
  const std::string log = slurp(d / "a" / "logs" / "datalink.log");
  CHECK(log.find("P_mean = P_peak/PF^2") != std::string::npos);
  CHECK(log.find("finished") != std::string::npos);
}

TEST_CASE("a lost message is detected, the realization repeated, the result unchanged",
          "[integration][loss]") {
  const fs::path d = scratch("loss");
  const std::string common = "--realizations 4 --seed 9 " + kFast;
  const auto clean = sh(kRun + common + "--out " + (d / "clean").string());
  // prl does not publish its PRL_APOI batch of realization 2, window 3, first attempt.
  const auto lossy = sh(kRun + common + "--drop prl:PRL_APOI:2:3:0 --out " + (d / "lossy").string());
  INFO(clean.output << lossy.output);
  REQUIRE(clean.status == 0);
  REQUIRE(lossy.status == 0);
  const auto ev = nlohmann::json::parse(slurp(d / "lossy" / "run_events.json"));
  REQUIRE(ev["retries"].size() == 1);
  CHECK(ev["retries"][0]["realization"] == 2);
  CHECK(ev["retries"][0]["reason"].get<std::string>().find("PRL_APOI") != std::string::npos);
  const auto ev_clean = nlohmann::json::parse(slurp(d / "clean" / "run_events.json"));
  CHECK(ev_clean["retries"].empty());
  CHECK(slurp(d / "lossy" / "stats_time.csv") == slurp(d / "clean" / "stats_time.csv"));
  CHECK(slurp(d / "lossy" / "table2.json") == slurp(d / "clean" / "table2.json"));
}

TEST_CASE("a message lost on every attempt fails the run naming it, no result is written",
          "[integration][loss]") {
  const fs::path d = scratch("loss_all");
  const auto r = sh(kRun + "--realizations 3 --seed 9 " + kFast +
                    "--drop snsins:NAV_SOLUTION:1:0 --out " + (d / "out").string());
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("NAV_SOLUTION") != std::string::npos);
  CHECK(r.output.find("realization 1 failed 3 times") != std::string::npos);
  CHECK_FALSE(fs::exists(d / "out"));
  CHECK_FALSE(fs::exists(d / "out.failed" / "table2.json"));
  CHECK(fs::exists(d / "out.failed" / "logs" / "clock.log"));
}

TEST_CASE("a process killed mid-run fails the run naming it", "[integration][kill]") {
  const fs::path d = scratch("kill");
  const fs::path out = d / "out";
  // Long enough to be mid-run when killed (a few seconds of lock-step).
  std::thread runner;
  Result r;
  runner = std::thread([&] { r = sh(kRun + "--realizations 3000 --seed 2 --out " + out.string()); });
  const pid_t prl = pid_in_run(d, "prl");
  REQUIRE(prl > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let it get going
  ::kill(prl, SIGKILL);
  runner.join();
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("process 'prl'") != std::string::npos);
  CHECK(r.output.find("killed by signal 9") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  CHECK_FALSE(fs::exists(d / "out.failed" / "table2.json"));
}

TEST_CASE("a batch lost once is published again: no repeated realization, the same result",
          "[integration][loss]") {
  const fs::path d = scratch("loss_once");
  const std::string common = "--realizations 4 --seed 9 " + kFast;
  const auto clean = sh(kRun + common + "--out " + (d / "clean").string());
  // prl's PRL_APOI batch of realization 2, window 3, attempt 0: only its first transmission lost.
  const auto lossy = sh(kRun + common + "--drop prl:PRL_APOI:2:3:0:1 --out " + (d / "lossy").string());
  INFO(clean.output << lossy.output);
  REQUIRE(clean.status == 0);
  REQUIRE(lossy.status == 0);
  const auto ev = nlohmann::json::parse(slurp(d / "lossy" / "run_events.json"));
  CHECK(ev["retries"].empty());
  // prl published it again on its consumers' WAITING (each consumer that missed it asks: prl_bias
  // and the logger, so one or two times); the consumers ignored any second copy.
  const std::string prl_log = slurp(d / "lossy" / "logs" / "prl.log");
  std::smatch m;
  REQUIRE(std::regex_search(prl_log, m, std::regex(R"(prl: finished \(\d+ resent batch\(es\) ignored, (\d+) republished\))")));
  CHECK(std::stoi(m[1]) >= 1);
  CHECK(slurp(d / "lossy" / "stats_time.csv") == slurp(d / "clean" / "stats_time.csv"));
  CHECK(slurp(d / "lossy" / "table2.json") == slurp(d / "clean" / "table2.json"));
}

TEST_CASE("random multicast loss of 1 % and 5 % and 20 % is recovered: the statistics equal a clean run's",
          "[integration][loss]") {
  // iptables drops each multicast packet with probability P inside the run's private network
  // namespace (scripts/run --loss). 50 realizations of one window each, about 17 datagrams a
  // window (batches of up to three): at 20 % some 170 are lost, and a republished batch is lost
  // again about half the time. The run must complete with byte-identical results.
  const fs::path d = scratch("loss_random");
  const std::string common = "--realizations 50 --seed 4 ";
  const auto clean = sh(kRun + common + "--out " + (d / "clean").string());
  INFO(clean.output);
  REQUIRE(clean.status == 0);
  for (const char* p : {"0.01", "0.05", "0.2"}) {
    const fs::path out = d / (std::string("loss") + p);
    const auto lossy = sh(kRun + common + "--loss " + p + " --out " + out.string());
    INFO("loss " << p << "\n" << lossy.output);
    REQUIRE(lossy.status == 0);
    CHECK(lossy.output.find("dropping each multicast packet with probability") != std::string::npos);
    const auto ev = nlohmann::json::parse(slurp(out / "run_events.json"));
    CHECK(ev["resends"].size() > 0);  // loss happened and was recovered
    CHECK(slurp(out / "stats_time.csv") == slurp(d / "clean" / "stats_time.csv"));
    CHECK(slurp(out / "stats_range.csv") == slurp(d / "clean" / "stats_range.csv"));
    CHECK(slurp(out / "table2.json") == slurp(d / "clean" / "table2.json"));
  }
}

namespace {
// Distinct messages per channel of an LCM event log (a resent copy counted once; lcm::LogFile,
// independent of the run's own check).
std::map<std::string, long> distinct_per_channel(const std::string& file) {
  lcm::LogFile log(file, "r");
  REQUIRE(log.good());
  std::map<std::string, std::set<std::string>> seen;
  while (const lcm::LogEvent* e = log.readNextEvent())
    seen[e->channel].insert(std::string(static_cast<const char*>(e->data), static_cast<std::size_t>(e->datalen)));
  std::map<std::string, long> n;
  for (const auto& [channel, messages] : seen) n[channel] = static_cast<long>(messages.size());
  return n;
}
}  // namespace

TEST_CASE("an LCM log recorded under multicast loss holds every message the nodes published and a copy lacking some is named",
          "[integration][loss][lcm_log]") {
  // --loss drops a packet before any receiver sees it, so lcm-logger misses what the nodes miss
  // and records the resends that repair it: the recording holds every distinct data message the
  // nodes published (their "published" lines, summed), exactly, and the run warns of none. A copy
  // of it without every third distinct PRL_APOI message (what a recorder whose socket buffer overflows
  // leaves) is named by the same check (rnav.lcmlog.recording_warnings, which scripts/run calls)
  // with both counts, and no other channel is.
  const fs::path d = scratch("loss_lcm_log");
  const std::string log = (d / "run.lcmlog").string(), cut = (d / "cut.lcmlog").string();
  const auto r = sh(kRun + "--realizations 10 --seed 4 --loss 0.2 --lcm-log " + log + " --out " + (d / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("run: warning: the LCM log") == std::string::npos);
  std::map<std::string, long> published;
  const std::regex line(R"(^[a-z_]+: published (.*)$)"), pair(R"(([A-Z0-9_]+)=(\d+))");
  for (const auto& f : fs::directory_iterator(d / "out" / "logs")) {
    std::istringstream in(slurp(f.path()));
    std::smatch m;
    for (std::string l; std::getline(in, l);)
      if (std::regex_match(l, m, line)) {
        const std::string rest = m[1];
        for (std::sregex_iterator it(rest.begin(), rest.end(), pair), end; it != end; ++it)
          published[(*it)[1]] += std::stol((*it)[2]);
      }
  }
  CHECK(published.size() == 6);  // TRUTH_AIRCRAFT, NAV_SOLUTION, PRL_APOI, TRUTH_PRL_ERROR, PRL_BIAS, PRL_TOI
  CHECK(published["PRL_APOI"] == 10);  // one batch per realization (one window each)
  const auto recorded = distinct_per_channel(log);
  for (const auto& [channel, n] : published) {
    INFO(channel);
    CHECK(recorded.count(channel) == 1);
    if (recorded.count(channel)) CHECK(recorded.at(channel) == n);
  }
  {
    // every copy of every third distinct PRL_APOI message left out: under loss the log also holds
    // resends, so leaving out every third event could leave out only copies of kept messages
    lcm::LogFile in(log, "r"), out(cut, "w");
    REQUIRE((in.good() && out.good()));
    std::map<std::string, long> order;  // payload -> its place among the distinct PRL_APOI messages
    while (const lcm::LogEvent* e = in.readNextEvent()) {
      if (e->channel == "PRL_APOI") {
        const std::string bytes(static_cast<const char*>(e->data), static_cast<std::size_t>(e->datalen));
        const long k = order.emplace(bytes, static_cast<long>(order.size())).first->second;
        if (k % 3 == 2) continue;
      }
      REQUIRE(out.writeEvent(const_cast<lcm::LogEvent*>(e)) == 0);
    }
  }
  const long kept = distinct_per_channel(cut).at("PRL_APOI");
  REQUIRE(kept == published["PRL_APOI"] - published["PRL_APOI"] / 3);
  const auto c = sh("PYTHONPATH='" + std::string(RNAV_SOURCE_DIR) + "/scripts' /usr/bin/python3 -c 'import sys; from rnav import "
                    "lcmlog; print(\"\\n\".join(lcmlog.recording_warnings(sys.argv[1], sys.argv[2])))' " + cut + " " +
                    (d / "out" / "logs").string());
  INFO(c.output);
  REQUIRE(c.status == 0);
  CHECK(c.output.find("run: warning: the LCM log holds " + std::to_string(kept) + " of the " +
                      std::to_string(published["PRL_APOI"]) + " distinct messages the nodes published on PRL_APOI:") !=
        std::string::npos);
  CHECK(std::count(c.output.begin(), c.output.end(), '\n') == 1);  // that one line, no other channel
}

TEST_CASE("loss that recovery cannot repair in time fails the run naming what was missing", "[integration][loss]") {
  // 50 % loss and 0.1 s to complete a window once (runner.ack_timeout_s, its least value, with
  // max_attempts 1): a window is about 17 datagrams, all arrive with probability 0.5^17 < 1e-5,
  // and a realization at 50 % loss takes about 1 s to recover (README); over 20 realizations
  // some window fails. The run must stop with the realization, the attempt and what the waiting
  // nodes missed.
  const fs::path d = scratch("loss_unrecoverable");
  const auto r = sh(kRun + "--realizations 20 --seed 4 --loss 0.5 --set runner.ack_timeout_s=0.1 "
                    "--set runner.max_attempts=1 --out " + (d / "out").string());
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("failed 1 times (runner.max_attempts)") != std::string::npos);
  CHECK(r.output.find("window not complete within") != std::string::npos);
  const bool named = r.output.find("waiting for realization") != std::string::npos ||
                     r.output.find(": no ack") != std::string::npos;
  CHECK(named);
  CHECK_FALSE(fs::exists(d / "out"));
}

TEST_CASE("a frozen clock fails the run naming it, within 2 s of the peer timeout", "[integration][watchdog]") {
  const fs::path d = scratch("frozen_clock");
  std::thread runner;
  Result r;
  runner = std::thread([&] {
    r = sh(kRun + "--realizations 3000 --seed 2 --set runner.peer_timeout_s=2 --out " + (d / "out").string());
  });
  const pid_t clock = pid_in_run(d, "clock");
  REQUIRE(clock > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(clock, SIGSTOP);
  const auto t0 = std::chrono::steady_clock::now();
  runner.join();
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ::kill(clock, SIGKILL);  // (the runner has killed it already)
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("the clock fell silent") != std::string::npos);
  CHECK(took < 2 + 2);
  CHECK_FALSE(fs::exists(d / "out"));
}

TEST_CASE("a frozen node fails the run naming it, within 2 s of the peer timeout", "[integration][watchdog]") {
  const fs::path d = scratch("frozen_node");
  std::thread runner;
  Result r;
  runner = std::thread([&] {
    r = sh(kRun + "--realizations 3000 --seed 2 --set runner.peer_timeout_s=2 --out " + (d / "out").string());
  });
  const pid_t snsins = pid_in_run(d, "snsins");
  REQUIRE(snsins > 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(snsins, SIGSTOP);
  const auto t0 = std::chrono::steady_clock::now();
  runner.join();
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("node 'snsins' fell silent") != std::string::npos);
  CHECK(took < 2 + 2);
  CHECK_FALSE(alive(snsins));  // the runner killed it (SIGKILL works on a stopped process)
}

TEST_CASE("killing the runner takes every process of the run with it", "[integration][watchdog]") {
  const fs::path d = scratch("kill_runner");
  // scripts/run in its own process group, so that it alone can be killed (not this test).
  const std::string cmd = "RNAV_BUILD='" + kBuild + "' setsid " + kRun + "--realizations 3000 --seed 2 --out " +
                          (d / "out").string() + " >" + (d / "run.log").string() + " 2>&1 & echo $!";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  int run_pid = 0;
  REQUIRE(fscanf(p, "%d", &run_pid) == 1);
  pclose(p);
  std::vector<pid_t> pids;
  for (const char* n : {"trajectory", "snsins", "prl", "prl_bias", "logger", "clock"}) {
    const pid_t pid = pid_in_run(d, n);
    REQUIRE(pid > 0);
    pids.push_back(pid);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(run_pid, SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  for (const pid_t pid : pids) {
    INFO("pid " << pid);
    CHECK_FALSE(alive(pid));
  }
}

TEST_CASE("an output folder that is not ours is refused (--out) and left intact", "[integration][files]") {
  const fs::path d = scratch("foreign_out");
  for (const char* name : {"mine", "mine2", "mine3"}) {
    fs::create_directories(d / name);
    std::ofstream(d / name / "thesis.txt") << "precious";
  }
  const auto run = sh(kRun + "--realizations 2 --out " + (d / "mine").string());
  const auto exp = sh(kBuild + "/bin/rnav_export_prl --scenario " + kRoot + "/sim/scenarios/paper.json --out " +
                      (d / "mine2").string());
  // scripts/run also removes DIR.failed and DIR.old: a foreign one is refused the same way.
  fs::create_directories(d / "fresh.failed");
  std::ofstream(d / "fresh.failed" / "notes.txt") << "mine";
  const auto failed = sh(kRun + "--realizations 2 --out " + (d / "fresh").string());
  INFO(run.output << exp.output << failed.output);
  CHECK(run.status != 0);
  CHECK(run.output.find("thesis.txt") != std::string::npos);
  CHECK(run.output.find("--force") != std::string::npos);
  CHECK(exp.status != 0);
  CHECK(exp.output.find("mine2") != std::string::npos);
  CHECK(failed.status != 0);
  CHECK(failed.output.find("fresh.failed") != std::string::npos);
  for (const char* name : {"mine", "mine2"}) {
    CHECK(slurp(d / name / "thesis.txt") == "precious");
    CHECK(std::distance(fs::directory_iterator(d / name), fs::directory_iterator()) == 1);
  }
  CHECK(slurp(d / "fresh.failed" / "notes.txt") == "mine");
  // An earlier output is replaced without --force; a foreign folder with it.
  REQUIRE(sh(kRun + "--realizations 2 --no-plots --out " + (d / "ours").string()).status == 0);
  CHECK(sh(kRun + "--realizations 2 --no-plots --out " + (d / "ours").string()).status == 0);
  CHECK(sh(kRun + "--realizations 2 --no-plots --force --out " + (d / "mine3").string()).status == 0);
  CHECK_FALSE(fs::exists(d / "mine3" / "thesis.txt"));
  CHECK(fs::exists(d / "mine3" / "table2.json"));

  // The single-process ensemble's --out follows the same rule; the ADS-B importer's --out is a
  // file, which is replaced only with --force.
  fs::create_directories(d / "mine4");
  std::ofstream(d / "mine4" / "thesis.txt") << "precious";
  const std::string inproc = kBuild + "/bin/rnav_inproc --scenario " + kRoot + "/sim/scenarios/paper.json --realizations 2 --out ";
  const auto in_foreign = sh(inproc + (d / "mine4").string());
  INFO(in_foreign.output);
  CHECK(in_foreign.status == 2);
  CHECK(in_foreign.output.find("thesis.txt") != std::string::npos);
  CHECK(slurp(d / "mine4" / "thesis.txt") == "precious");
  CHECK(sh(inproc + (d / "mine4").string() + " --force").status == 0);
  CHECK(fs::exists(d / "mine4" / "stats_time.csv"));
  std::ofstream(d / "approach.csv") << "precious";
  const std::string adsb = kBuild + "/bin/rnav_import_adsb " + kData + "/adsb/vienna.json.gz --approach 2 --out " +
                           (d / "approach.csv").string();
  const auto ad_exists = sh(adsb);
  INFO(ad_exists.output);
  CHECK(ad_exists.status == 2);
  CHECK(ad_exists.output.find("exists; pass --force") != std::string::npos);
  CHECK(slurp(d / "approach.csv") == "precious");
  CHECK(sh(adsb + " --force").status == 0);
  CHECK(slurp(d / "approach.csv").rfind("t_s,lat_deg,lon_deg,h_m", 0) == 0);
}

TEST_CASE("a full disk is an error naming the file, not a truncated result", "[integration][files]") {
  // A 64 kB tmpfs in a private mount namespace (root, or a user namespace); the export of one
  // approach writes about 300 kB of CSV, so some write fails with ENOSPC.
  const fs::path d = scratch("full_disk");
  const std::string inner = "mount -t tmpfs -o size=64k tmpfs " + d.string() + " && " + kBuild +
                            "/bin/rnav_export_prl --scenario " + kRoot + "/sim/scenarios/paper.json --out " +
                            (d / "x").string();
  Result r = sh("unshare -m sh -c '" + inner + "'");
  if (r.output.find("mount") != std::string::npos || r.output.find("unshare") != std::string::npos)
    r = sh("unshare -rm sh -c '" + inner + "'");
  if (r.output.find("rnav_export_prl") == std::string::npos && r.output.find("export:") == std::string::npos) {
    WARN("no private mount namespace here (" << r.output << "): the full-disk case is not exercised");
    return;
  }
  INFO(r.output);
  CHECK(r.status != 0);
  CHECK(r.output.find("No space left on device") != std::string::npos);
  CHECK(r.output.find(".partial") != std::string::npos);  // the file it was writing, named
}

TEST_CASE("bad scenario input is an error naming the key", "[integration][input]") {
  const fs::path d = scratch("bad");
  const std::string out = " --out " + (d / "out").string();
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"--set prl.bias_rang_m=6", "prl.bias_rang_m"},
      {"--set prl.noise2s_range_m=NaN", "prl.noise2s_range_m"},
      {"--set prl.noise2s_range_m=-3", "prl.noise2s_range_m"},
      {"--set snsins.latency_s=true", "snsins.latency_s"},
      {"--set prl.period_s=0.3", "prl.period_s"},
      {"--set trajectory.bank_deg=2", "trajectory"},
      {"--realizations zero", "--realizations"},
  };
  for (const auto& c : cases) {
    const auto r = sh(kRun + "--realizations 2 " + c.args + out);
    INFO(c.args << "\n" << r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(d / "out"));
  }
  // A malformed scenario file names the file.
  std::ofstream(d / "broken.json") << "{\"prl\": {\"period_s\": 1,,}}";
  const auto r = sh(kRoot + "/scripts/run " + (d / "broken.json").string() + " --no-plots" + out);
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("broken.json") != std::string::npos);
}

TEST_CASE("real-time mode is paced by the wall clock and gives the lock-step statistics",
          "[integration][realtime]") {
  const fs::path d = scratch("realtime");
  // The paper approach lasts about 500 s of sim time; at speed 200 that is >= 2.5 s of wall time.
  const auto t0 = std::chrono::steady_clock::now();
  const auto rt = sh(kRun + "--realizations 1 --seed 4 --realtime --speed 200 --out " +
                     (d / "rt").string());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto ls = sh(kRun + "--realizations 1 --seed 4 --out " + (d / "ls").string());
  INFO(rt.output << ls.output);
  REQUIRE(rt.status == 0);
  REQUIRE(ls.status == 0);
  CHECK(wall >= 2.4);  // not faster than the requested pace
  CHECK(slurp(d / "rt" / "stats_time.csv") == slurp(d / "ls" / "stats_time.csv"));
}

TEST_CASE("UAV scenario: multi-process over LCM equals one process, summary has the documented shape",
          "[integration][uav]") {
  const fs::path d = scratch("uav");
  // All four estimators: the list value of tma.estimators reaches every process through --set, and
  // the particle filter's random draws are the same in the uav_tma process as in one process.
  const std::string uav = kRoot + "/scripts/run uav --no-plots --net netns --realizations 10 --seed 3 "
                          "--set 'tma.estimators=[\"ekf\",\"rpekf\",\"ml\",\"pf\"]' --set tma.pf_particles=2000 ";
  const auto mp = sh(uav + "--out " + (d / "mp").string());
  const auto ip = sh(uav + "--inproc --out " + (d / "ip").string());
  INFO(mp.output << ip.output);
  REQUIRE(mp.status == 0);
  REQUIRE(ip.status == 0);
  for (const char* f : {"uav_stats_time.csv", "summary.json", "realizations.csv", "track.csv", "scenario.json"}) {
    INFO(f);
    REQUIRE(slurp(d / "mp" / f).size() > 100);
    CHECK(slurp(d / "mp" / f) == slurp(d / "ip" / f));
  }
  const auto j = nlohmann::json::parse(slurp(d / "mp" / "summary.json"));
  CHECK(j["pcrb_pos_m"].get<double>() > 0);
  CHECK(j["estimators"].size() == 4);
  for (const char* e : {"ekf", "rpekf", "ml", "pf"}) {
    INFO(e);
    const auto& s = j["estimators"][e];
    CHECK(s["rmse_pos_m"].get<double>() > 0);
    CHECK(s["nees_band"].size() == 2);
    CHECK(s["nees_band"][0].get<double>() < 4.0);
    CHECK(s["nees_band"][1].get<double>() > 4.0);
    CHECK(s.contains("diverged"));
  }
  for (const char* n : {"target", "uav", "uav_tma", "uav_logger"})
    CHECK(slurp(d / "mp" / "logs" / (std::string(n) + ".log")).find("finished") != std::string::npos);
}

TEST_CASE("UAV closed loop gives the same summary across transports and wire forms and window sizes and steers",
          "[integration][uav][guidance][determinism]") {
  // The guidance at time t uses the estimate of t - uav.estimate_latency_s (1 s), published in an
  // earlier window whatever the window size: multi-process over LCM (batch and sample wire) and one
  // process with windows of 0.2 s and 1 s must give byte-identical files.
  const fs::path d = scratch("uav_loop");
  const std::string uav = kRoot + "/scripts/run uav --no-plots --realizations 4 --seed 8 --set target.speed_mps=5 "
                                  "--set uav.guidance=estimate --set uav.wind_east_mps=4 ";
  const auto mp = sh(uav + "--net netns --out " + (d / "mp").string());
  const auto ms = sh(uav + "--net netns --set runner.wire=sample --out " + (d / "ms").string());
  const auto ip = sh(uav + "--inproc --set runner.window_s=0.2 --out " + (d / "ip").string());
  const auto ip1 = sh(uav + "--inproc --set runner.window_s=1 --out " + (d / "ip1").string());
  const auto late = sh(kRoot + "/scripts/run uav --no-plots --inproc --realizations 4 --seed 8 --set target.speed_mps=5 "
                              "--set uav.guidance=estimate --set uav.estimate_latency_s=5 --out " + (d / "late").string());
  INFO(mp.output << ms.output << ip.output << ip1.output << late.output);
  REQUIRE(mp.status == 0);
  REQUIRE(ms.status == 0);
  REQUIRE(ip.status == 0);
  REQUIRE(ip1.status == 0);
  REQUIRE(late.status == 0);
  for (const char* f : {"summary.json", "uav_stats_time.csv", "realizations.csv"}) {  // (scenario.json names wire and window)
    INFO(f);
    const std::string ref = slurp(d / "mp" / f);
    REQUIRE(ref.size() > 100);
    CHECK(slurp(d / "ms" / f) == ref);
    CHECK(slurp(d / "ip" / f) == ref);
    CHECK(slurp(d / "ip1" / f) == ref);
  }
  const auto j = nlohmann::json::parse(slurp(d / "mp" / "summary.json"));
  CHECK(j["guidance"] == "estimate");
  // The loop steers: the object (5 m/s, 940 m in two orbits) stays within the 300 m orbit.
  CHECK(j["object_inside_orbit_runs"] == 4);
  CHECK(j["object_range_m"]["max"].get<double>() < 600);
  // ... and what is fed back matters: a 5 s old estimate changes the path, hence the results.
  CHECK(slurp(d / "late" / "summary.json") != slurp(d / "ip" / "summary.json"));
}

TEST_CASE("UAV scenario: bad input is an error naming the key", "[integration][uav][input]") {
  const fs::path d = scratch("uav_bad");
  const std::string uav = kRoot + "/scripts/run uav --no-plots --realizations 2 --out " + (d / "o").string();
  struct Case {
    std::string args, expect;
  };
  for (const Case& c : {Case{"--set uav.path=circel", "uav.path"},
                        Case{"--set sensor.sigma_deg=0", "sensor.sigma_deg"},
                        Case{"--set uav.radius_mm=300", "uav.radius_mm"},
                        Case{"--set target.manoeuvres=[[1,2,3]]", "target.manoeuvres"},
                        Case{"--set sensor.period_s=NaN", "sensor.period_s"},
                        Case{"--set uav.guidance=estimat", "did you mean 'estimate'"},
                        Case{"--set uav.guidance=los --set runner.window_s=2", "uav.estimate_latency_s"},
                        Case{"--set runner.window_s=0", "must be > 0 in the UAV scenario"},
                        Case{"--set uav.guidance=estimate --set uav.path=straight", "uav.path"},
                        Case{"--set uav.guidance=los --set uav.wind_north_mps=20", "uav.wind_north_mps"},
                        Case{"--set uav.guidance=los --set uav.estimate_latency_s=0.3", "uav.estimate_latency_s"},
                        Case{"--set uav.guidance_estimator=kf", "uav.guidance_estimator"},
                        Case{"--set uav.max_bank_deg=90", "uav.max_bank_deg"},
                        Case{"--set 'tma.estimators=[\"ekf\",\"mll\"]'",
                             "'tma.estimators': 'mll' is not one of ekf, rpekf, ml, pf (did you mean 'ml'?)"},
                        Case{"--set tma.estimators=ml", "'tma.estimators': expected a list of strings"}}) {
    const auto r = sh(uav + " " + c.args);
    INFO(c.args << "\n" << r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(d / "o"));
  }
}

TEST_CASE("run with lcm-logger: the log records the run and diagnose reads the log and names the hidden effect",
          "[integration][lcm_log]") {
  const fs::path d = scratch("lcm_log");
  const std::string log = (d / "run.lcmlog").string();
  // Realization 1 loses a batch in its first attempt, so the log holds two attempts of it.
  const auto r = sh(kRun + "--realizations 2 --seed 7 " + kFast +
                    "--set prl_effects.range_gain=0.002 --drop prl:PRL_APOI:1:2:0 --lcm-log " + log +
                    " --out " + (d / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  REQUIRE(fs::exists(log));
  CHECK_FALSE(fs::exists(log + ".partial"));
  const std::string diag = kBuild + "/bin/rnav_diagnose prl --injections 0 " + log + " --realization 1";
  const auto with_file = sh(diag + " --scenario " + kRoot + "/sim/scenarios/paper.json");
  const auto embedded = sh(diag);  // the scenario from the log's SIM_SCENARIO
  INFO(with_file.output << embedded.output);
  REQUIRE(with_file.status == 0);
  REQUIRE(embedded.status == 0);
  CHECK(with_file.output.find("realization 1 attempt 1") != std::string::npos);
  CHECK(with_file.output.find("of earlier attempts") != std::string::npos);
  const auto at = with_file.output.find("EFFECT   range_gain: g=");
  REQUIRE(at != std::string::npos);
  double g = 0, se = 0;
  REQUIRE(std::sscanf(with_file.output.c_str() + at, "EFFECT   range_gain: g=%lf +- %lf", &g, &se) == 2);
  CHECK(std::abs(g - 0.002) <= 3 * se);
  // The two scenario sources give the same report (only the summary line names the source).
  auto report = [](const std::string& s) { return s.substr(s.find("\nplots used")); };
  CHECK(report(with_file.output) == report(embedded.output));
  // Another realization and a missing one.
  const auto r2 = sh(diag.substr(0, diag.size() - 1) + "5");
  CHECK(r2.status == 2);
  CHECK(r2.output.find("realization 5 is not in the log; realizations present: 0-1") != std::string::npos);

  // A failed run leaves the partial log beside FILE, never FILE itself.
  const std::string log2 = (d / "failed.lcmlog").string();
  const auto f = sh(kRun + "--realizations 2 --seed 7 " + kFast + "--drop snsins:NAV_SOLUTION:1:0 --lcm-log " +
                    log2 + " --out " + (d / "out2").string());
  INFO(f.output);
  CHECK(f.status != 0);
  CHECK_FALSE(fs::exists(log2));
  CHECK(fs::exists(log2 + ".partial"));
  // ... in which the failed realization is named as incomplete.
  const auto d2 = sh(kBuild + "/bin/rnav_diagnose prl --injections 0 " + log2 + ".partial --realization 1");
  CHECK(d2.status == 2);
  CHECK(d2.output.find("did not complete") != std::string::npos);
  // --lcm-log needs the multi-process run.
  const auto inproc = sh(kRun + "--realizations 1 --inproc --lcm-log " + log2 + " --out " + (d / "out3").string());
  CHECK(inproc.status == 2);
  CHECK(inproc.output.find("--lcm-log") != std::string::npos);
}

TEST_CASE("diagnose: INPUT is a CSV folder or an LCM log, anything else is named", "[integration][lcm_log][input]") {
  const fs::path d = scratch("diag_input");
  std::ofstream(d / "notes.txt") << "not a log\n";
  const std::string diag = kBuild + "/bin/rnav_diagnose prl ";
  const auto text = sh(diag + (d / "notes.txt").string());
  CHECK(text.status == 2);
  CHECK(text.output.find("notes.txt' is neither a CSV folder nor an LCM event log") != std::string::npos);
  const auto none = sh(diag + (d / "missing").string());
  CHECK(none.status == 2);
  CHECK(none.output.find("missing': no such file or directory") != std::string::npos);
  // Log options on a CSV folder are refused, not ignored.
  fs::create_directories(d / "csv");
  const auto csv = sh(diag + (d / "csv").string() + " --realization 1");
  CHECK(csv.status == 2);
  CHECK(csv.output.find("is a CSV folder") != std::string::npos);
}
