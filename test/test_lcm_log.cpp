// LCM event logs as diagnose input (estimators/diagnosis/io/lcm_log_*): a log of an in-process run
// gives exactly the flight the CSV exporter writes (and the same diagnosis), uses the attempt
// the clock accepted and ignores earlier ones, and every kind of damage to a log is an error
// naming channel, realization, attempt, window and file.
#include <catch2/catch.hpp>

#include "common/node/batch_decode.hpp"
#include "common/node/channels.hpp"
#include "common/io/config.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "scripts/compose/export/lcm_log_export.hpp"
#include "estimators/diagnosis/io/lcm_log_input.hpp"
#include "estimators/diagnosis/io/lcm_log_streams.hpp"
#include "estimators/diagnosis/prl_diagnose.hpp"
#include "scripts/compose/export/prl_export.hpp"
#include "sim/target/target_node.hpp"
#include "test/test_support.hpp"
#include "estimators/diagnosis/uav_diagnose.hpp"
#include "sim/uav/uav_node.hpp"

#include <lcm/lcm-cpp.hpp>
#include <unistd.h>
#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/bearing_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>
#include <rnav/sim_window_t.hpp>
#include <rnav/target_truth_batch_t.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

namespace fs = std::filesystem;
using namespace rnav;
using rnav_test::slurp;

namespace {

const std::string kPaper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";
const std::string kUav = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/uav.json";

fs::path scratch(const std::string& name) {
  return rnav_test::fresh_dir(fs::temp_directory_path() / ("rnav_test_lcm_log_" + name));
}

struct Event {
  std::string channel;
  std::vector<std::uint8_t> data;
};

std::vector<Event> read_events(const std::string& file) {
  lcm::LogFile log(file, "r");
  REQUIRE(log.good());
  std::vector<Event> out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* p = static_cast<const std::uint8_t*>(e->data);
    out.push_back({e->channel, std::vector<std::uint8_t>(p, p + e->datalen)});
  }
  return out;
}

void write_events(const std::string& file, const std::vector<Event>& events) {
  lcm::LogFile log(file, "w");
  REQUIRE(log.good());
  std::int64_t t = 0;
  for (const auto& ev : events) {
    lcm::LogEvent e;
    e.eventnum = 0;
    e.timestamp = t++;
    e.channel = ev.channel;
    e.datalen = static_cast<int>(ev.data.size());
    e.data = const_cast<std::uint8_t*>(ev.data.data());
    REQUIRE(log.writeEvent(&e) == 0);
  }
}

template <class B> B decode(const Event& e) {
  B b;
  REQUIRE(b.decode(e.data.data(), 0, static_cast<int>(e.data.size())) == static_cast<int>(e.data.size()));
  return b;
}

template <class B> Event encode(const std::string& channel, const B& b) {
  Event e{channel, std::vector<std::uint8_t>(static_cast<std::size_t>(b.getEncodedSize()))};
  b.encode(e.data.data(), 0, static_cast<int>(e.data.size()));
  return e;
}

// Index of the event on `channel` (a batch type with a header) of (r, a, w).
template <class B> std::size_t find_batch(const std::vector<Event>& ev, const std::string& channel, int r, int a, int w) {
  for (std::size_t i = 0; i < ev.size(); ++i)
    if (ev[i].channel == channel) {
      const B b = decode<B>(ev[i]);
      if (b.header.realization == r && b.header.attempt == a && b.header.window == w) return i;
    }
  FAIL("no " << channel << " batch of realization " << r << " attempt " << a << " window " << w);
  return 0;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

// One paper log for several tests: 2 realizations with a hidden time offset; realization 1
// loses its PRL_APOI batch of window 2 in attempt 0, so it is repeated as attempt 1.
// 100 s windows: these logs hold several windows per realization (the landing default is one),
// so that damage can be put into one window and named by it.
const std::vector<std::string> kEffect = {"prl_effects.time_offset_s=0.4", "runner.window_s=100"};
const std::int64_t kSeed = 5;

const std::string& paper_log() {
  static std::string file;
  if (file.empty()) {
    const fs::path d = scratch("paper_" + std::to_string(::getpid()));  // ctest -j: one per process
    const std::string f = (d / "run.lcmlog").string();
    std::string failure;
    REQUIRE(export_lcm_log(kPaper, kEffect, kSeed, 2, f, {"PRL_APOI:1:2:0"}, &failure) == 0);
    file = f;
  }
  return file;
}

LcmLogOptions realization(int r) {
  LcmLogOptions o;
  o.realization = r;
  return o;
}

}  // namespace

TEST_CASE("lcm log: the repeated realization equals the CSV export, byte for byte, and diagnoses the same",
          "[lcm_log]") {
  const std::string log = paper_log();
  std::string summary;
  const PrlFlightData from_log = read_prl_lcm_log(log, realization(1), &summary);
  INFO(summary);
  CHECK(summary.find("realization 1 attempt 1") != std::string::npos);  // the repeat was used
  CHECK(summary.find("scenario from the log's SIM_SCENARIO") != std::string::npos);

  const fs::path d = scratch("paper_csv");
  REQUIRE(export_prl_flight(Scenario::load(kPaper, kEffect), kSeed, 1, (d / "csv").string()) == 0);
  from_log.write_folder((d / "log").string());
  for (const char* f : {"site.json", "radar.csv", "nav.csv", "truth.csv"}) {
    INFO(f);
    const std::string ref = slurp(d / "csv" / f);
    REQUIRE(ref.size() > 100);
    CHECK(slurp(d / "log" / f) == ref);
  }
  // Another realization is other data (the comparison above can fail).
  PrlFlightData::read_folder((d / "csv").string());
  read_prl_lcm_log(log, realization(0)).write_folder((d / "r0").string());
  CHECK(slurp(d / "r0" / "radar.csv") != slurp(d / "csv" / "radar.csv"));

  // The diagnosis of the log (full precision) and of the CSV folder name the same effects
  // with the same estimates (to far below their standard errors).
  const DiagnoseReport a = diagnose_prl(from_log, DiagnoseOptions{});
  const DiagnoseReport b = diagnose_prl(PrlFlightData::read_folder((d / "csv").string()), DiagnoseOptions{});
  INFO(a.text() << "\n---\n" << b.text());
  REQUIRE(a.effects.size() == b.effects.size());
  bool found = false;
  for (std::size_t i = 0; i < a.effects.size(); ++i) {
    CHECK(a.effects[i].name == b.effects[i].name);
    REQUIRE(a.effects[i].estimate.size() == b.effects[i].estimate.size());
    for (std::size_t k = 0; k < a.effects[i].estimate.size(); ++k)
      CHECK(std::abs(a.effects[i].estimate[k] - b.effects[i].estimate[k]) <= 0.01 * b.effects[i].stderr_[k]);
    found |= a.effects[i].name == "time_offset";
  }
  CHECK(found);
}

TEST_CASE("lcm log: batches of the failed attempt are ignored, whatever they hold", "[lcm_log]") {
  auto ev = read_events(paper_log());
  // Attempt 0 of realization 1 is in the log up to the lost window: make every batch of it
  // nonsense; the result must not change.
  int changed = 0;
  for (auto& e : ev)
    if (e.channel == ch::kApoi || e.channel == ch::kTruth) {
      if (e.channel == ch::kApoi) {
        auto b = decode<prl_plot_batch_t>(e);
        if (b.header.realization != 1 || b.header.attempt != 0) continue;
        for (auto& p : b.plots) p.range_m += 5000;
        e = encode(ch::kApoi, b);
        ++changed;
      }
    }
  REQUIRE(changed >= 2);  // windows 0 and 1 (window 2 was lost, so the attempt stopped)
  const fs::path d = scratch("attempts");
  write_events((d / "mod.lcmlog").string(), ev);
  read_prl_lcm_log((d / "mod.lcmlog").string(), realization(1)).write_folder((d / "mod").string());
  read_prl_lcm_log(paper_log(), realization(1)).write_folder((d / "ref").string());
  CHECK(slurp(d / "mod" / "radar.csv") == slurp(d / "ref" / "radar.csv"));
  // While the same change to the accepted attempt does show (the check above can fail).
  for (auto& e : ev)
    if (e.channel == ch::kApoi) {
      auto b = decode<prl_plot_batch_t>(e);
      if (b.header.realization != 1 || b.header.attempt != 1 || b.header.window != 1) continue;
      for (auto& p : b.plots) p.range_m += 5000;
      e = encode(ch::kApoi, b);
    }
  write_events((d / "mod2.lcmlog").string(), ev);
  read_prl_lcm_log((d / "mod2.lcmlog").string(), realization(1)).write_folder((d / "mod2").string());
  CHECK(slurp(d / "mod2" / "radar.csv") != slurp(d / "ref" / "radar.csv"));
}

TEST_CASE("lcm log: damage is an error naming channel, realization, attempt, window and file",
          "[lcm_log][input]") {
  const auto ev = read_events(paper_log());
  const fs::path d = scratch("damage");
  auto with = [&](const std::string& name, const std::vector<Event>& events, int r = 1) {
    const std::string f = (d / name).string();
    write_events(f, events);
    return error_of([&] { read_prl_lcm_log(f, realization(r)); });
  };

  SECTION("a missing window") {
    auto v = ev;
    v.erase(v.begin() + static_cast<long>(find_batch<aircraft_truth_batch_t>(v, ch::kTruth, 1, 1, 3)));
    const std::string e = with("missing.lcmlog", v);
    CHECK_THAT(e, Catch::Contains("missing.lcmlog") && Catch::Contains("TRUTH_AIRCRAFT, realization 1, attempt 1") &&
                      Catch::Contains("window 3 is missing"));
  }
  SECTION("the last window missing") {
    auto v = ev;
    int last = -1;
    for (const auto& e : v)
      if (e.channel == ch::kWindow && decode<sim_window_t>(e).last_window) last = decode<sim_window_t>(e).window;
    REQUIRE(last > 0);
    v.erase(v.begin() + static_cast<long>(find_batch<nav_batch_t>(v, ch::kNav, 1, 1, last)));
    CHECK_THAT(with("last.lcmlog", v), Catch::Contains("NAV_SOLUTION, realization 1, attempt 1: window " +
                                                       std::to_string(last) + " is missing"));
  }
  SECTION("a duplicated batch that differs from the first copy") {
    // An identical copy is a resend (loss recovery publishes a batch again; see the next section).
    auto v = ev;
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, 2);
    auto b = decode<prl_plot_batch_t>(v[i]);
    REQUIRE(!b.plots.empty());
    b.plots[0].range_m += 1;
    v.insert(v.begin() + static_cast<long>(i) + 1, encode(ch::kApoi, b));
    CHECK_THAT(with("dup.lcmlog", v), Catch::Contains("PRL_APOI, realization 1, attempt 1") &&
                                          Catch::Contains("window 2") && Catch::Contains("duplicate") &&
                                          Catch::Contains("differs"));
  }
  SECTION("an identical resent copy is ignored, and a RESEND stands for a grant the log lost") {
    auto v = ev;
    const std::size_t i = find_batch<nav_batch_t>(v, ch::kNav, 1, 1, 2);
    v.insert(v.begin() + static_cast<long>(i) + 3, v[i]);
    // The START of realization 1 attempt 1 window 3 lost by the recorder, its RESEND kept.
    for (auto& e : v)
      if (e.channel == ch::kWindow) {
        auto w = decode<sim_window_t>(e);
        if (w.command != sim_window_t::START || w.realization != 1 || w.attempt != 1 || w.window != 3) continue;
        w.command = sim_window_t::RESEND;
        e = encode(ch::kWindow, w);
      }
    const std::string f = (d / "resent.lcmlog").string();
    write_events(f, v);
    read_prl_lcm_log(f, realization(1)).write_folder((d / "resent").string());
    read_prl_lcm_log(paper_log(), realization(1)).write_folder((d / "ref").string());
    for (const char* csv : {"radar.csv", "nav.csv", "truth.csv"}) {
      INFO(csv);
      REQUIRE(slurp(d / "ref" / csv).size() > 100);
      CHECK(slurp(d / "resent" / csv) == slurp(d / "ref" / csv));
    }
  }
  SECTION("an identical resent copy of the last window, after it, is ignored") {
    // The clock's RESEND of a realization's last window makes its publishers send it again; a
    // recorder may hold that copy after every window of the attempt (seen in CI under load).
    auto v = ev;
    int last = -1;
    for (const auto& e : v)
      if (e.channel == ch::kWindow && decode<sim_window_t>(e).last_window) last = decode<sim_window_t>(e).window;
    REQUIRE(last > 0);
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, last);
    v.insert(v.begin() + static_cast<long>(i) + 2, v[i]);
    const std::string f = (d / "resent_last.lcmlog").string();
    write_events(f, v);
    read_prl_lcm_log(f, realization(1)).write_folder((d / "resent_last").string());
    read_prl_lcm_log(paper_log(), realization(1)).write_folder((d / "ref_last").string());
    CHECK(slurp(d / "resent_last" / "radar.csv") == slurp(d / "ref_last" / "radar.csv"));
    // A copy that differs (here: one plot more) is still an error.
    auto b = decode<prl_plot_batch_t>(v[i]);
    b.plots.push_back(prl_plot_t{});
    b.n = static_cast<std::int32_t>(b.plots.size());
    v[i + 2] = encode(ch::kApoi, b);
    CHECK_THAT(with("resent_last_differs.lcmlog", v), Catch::Contains("PRL_APOI, realization 1, attempt 1") &&
                                                          Catch::Contains("differs"));
  }
  SECTION("a reordered batch") {
    auto v = ev;
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, 2);
    const std::size_t j = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, 3);
    std::swap(v[i], v[j]);
    CHECK_THAT(with("reorder.lcmlog", v), Catch::Contains("PRL_APOI, realization 1, attempt 1: window 2 is out of order"));
  }
  SECTION("a realization that is not in the log") {
    CHECK_THAT(with("r7.lcmlog", ev, 7), Catch::Contains("realization 7 is not in the log; realizations present: 0-1"));
  }
  SECTION("an undecodable message on a known channel") {
    auto v = ev;
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 0, 0, 1);
    v[i].data.resize(7);
    CHECK_THAT(with("garbage.lcmlog", v),
               Catch::Contains("event " + std::to_string(i) + " on channel PRL_APOI does not decode"));
  }
  SECTION("a batch whose count claims 2^31 - 1 elements (found by fuzzing: it asked for ~100 GB)") {
    auto v = ev;
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, 2);
    const auto at = static_cast<std::size_t>(rnav::batch_count_offset());  // the count n
    REQUIRE(v[i].data.size() > at + 4);
    v[i].data[at] = 0x7f, v[i].data[at + 1] = 0xff, v[i].data[at + 2] = 0xff, v[i].data[at + 3] = 0xff;
    CHECK_THAT(with("count.lcmlog", v),
               Catch::Contains("event " + std::to_string(i) + " on channel PRL_APOI does not decode"));
  }
  SECTION("event headers that lie: a size of 2^31 - 1, a cut file, a lost sync word, a repeated event number") {
    // The bounded reader checks every size against the file before reading (liblcm's reader
    // allocated what the header claimed and crashed).
    const std::string f = (d / "raw.lcmlog").string();
    write_events(f, ev);
    std::string bytes = slurp(f);
    const std::size_t second = 28 + ev[0].channel.size() + ev[0].data.size();  // offset of event 1
    auto patched = [&](const std::string& name, const std::string& b) {
      const std::string g = (d / name).string();
      std::ofstream(g, std::ios::binary) << b;
      return error_of([&] { read_prl_lcm_log(g, realization(1)); });
    };
    std::string huge = bytes;
    huge[second + 24] = '\x7f', huge[second + 25] = '\xff', huge[second + 26] = '\xff', huge[second + 27] = '\xff';
    CHECK_THAT(patched("huge.lcmlog", huge), Catch::Contains("huge.lcmlog: event 1 (byte " + std::to_string(second) + ")") &&
                                                 Catch::Contains("data length 2147483647 outside"));
    CHECK_THAT(patched("cut.lcmlog", bytes.substr(0, bytes.size() - 5)), Catch::Contains("the log was cut"));
    std::string nosync = bytes;
    nosync[second] = 0;
    CHECK_THAT(patched("nosync.lcmlog", nosync), Catch::Contains("event 1 (byte " + std::to_string(second) + "): no sync word"));
    std::string renum = bytes;
    for (int k = 4; k < 12; ++k) renum[second + static_cast<std::size_t>(k)] = 0;  // event 1 numbered 0 again
    CHECK_THAT(patched("renum.lcmlog", renum), Catch::Contains("event number 0 after 0"));
  }
  SECTION("a log cut before the clock moved on") {
    auto v = ev;
    // Up to the last window's grant of realization 1 (its batches and the FINISH cut off).
    auto last_grant = [](const Event& e) {
      if (e.channel != ch::kWindow) return false;
      const auto w = decode<sim_window_t>(e);
      return w.command == sim_window_t::START && w.last_window;
    };
    while (!last_grant(v.back())) v.pop_back();
    CHECK_THAT(with("cut.lcmlog", v), Catch::Contains("realization 1 attempt 1 (the last one in the log) did not complete"));
    // Realization 0 is complete in the same log.
    CHECK_NOTHROW(read_prl_lcm_log((d / "cut.lcmlog").string(), realization(0)));
  }
  SECTION("no scenario in the log and none given; --scenario then works, a wrong one is refused") {
    auto v = ev;
    v.erase(std::remove_if(v.begin(), v.end(), [](const Event& e) { return e.channel == ch::kScenario; }), v.end());
    CHECK_THAT(with("noscen.lcmlog", v), Catch::Contains("no SIM_SCENARIO") && Catch::Contains("--scenario"));
    LcmLogOptions o = realization(1);
    o.scenario_file = kPaper;
    const std::string f = (d / "noscen.lcmlog").string();
    read_prl_lcm_log(f, o).write_folder((d / "given").string());
    read_prl_lcm_log(paper_log(), realization(1)).write_folder((d / "embedded").string());
    CHECK(slurp(d / "given" / "site.json") == slurp(d / "embedded" / "site.json"));
    o.overrides = {"runner.epoch_utime=1767225700000000"};
    CHECK_THAT(error_of([&] { read_prl_lcm_log(f, o); }), Catch::Contains("not the scenario of this run"));
    o.overrides.clear();
    o.scenario_file = kUav;
    CHECK_THAT(error_of([&] { read_prl_lcm_log(f, o); }), Catch::Contains("is a 'uav' scenario"));
  }
  SECTION("not a log") {
    std::ofstream(d / "text.csv") << "t_s,range_m\n1,2\n";
    CHECK_FALSE(is_lcm_log((d / "text.csv").string()));
    CHECK(is_lcm_log(paper_log()));
    CHECK_THAT(error_of([&] { read_prl_lcm_log((d / "text.csv").string(), realization(0)); }),
               Catch::Contains("text.csv: not an LCM event log"));
  }
  SECTION("a radar log read as azimuth data") {
    CHECK_THAT(error_of([&] { read_uav_lcm_log(paper_log(), realization(0)); }),
               Catch::Contains("the log holds a 'prl' run (SIM_SCENARIO), not a 'uav' one"));
    // Without SIM_SCENARIO, the missing streams say it.
    auto v = ev;
    v.erase(std::remove_if(v.begin(), v.end(), [](const Event& e) { return e.channel == ch::kScenario; }), v.end());
    write_events((d / "noscen.lcmlog").string(), v);
    CHECK_THAT(error_of([&] { read_uav_lcm_log((d / "noscen.lcmlog").string(), realization(0)); }),
               Catch::Contains("UAV_NAV, realization 0, attempt 0: window 0 is missing"));
  }
}

TEST_CASE("lcm log and CSV: values out of their physical range and corrupt time stamps are named, not used",
          "[lcm_log][input]") {
  const auto ev = read_events(paper_log());
  const fs::path d = scratch("values");
  auto log_error = [&](const std::string& name, const std::vector<Event>& events) {
    const std::string f = (d / name).string();
    write_events(f, events);
    return error_of([&] { read_prl_lcm_log(f, realization(1)); });
  };
  auto with_plot = [&](const std::function<void(rnav::prl_plot_t&)>& change) {
    auto v = ev;
    const std::size_t i = find_batch<prl_plot_batch_t>(v, ch::kApoi, 1, 1, 2);
    auto b = decode<prl_plot_batch_t>(v[i]);
    REQUIRE(b.plots.size() > 3);
    change(b.plots[3]);
    v[i] = encode(ch::kApoi, b);
    return v;
  };
  // One flipped bit (bit 40) in a plot's time stamp: outside its batch's window (was: dropped).
  CHECK_THAT(log_error("bit.lcmlog", with_plot([](rnav::prl_plot_t& p) { p.utime ^= std::int64_t{1} << 40; })),
             Catch::Contains("PRL_APOI, realization 1, window 2") && Catch::Contains("outside the batch's window"));
  CHECK_THAT(log_error("nan.lcmlog", with_plot([](rnav::prl_plot_t& p) { p.range_m = NAN; })),
             Catch::Contains("radar plot") && Catch::Contains("range nan m outside"));
  CHECK_THAT(log_error("huge.lcmlog", with_plot([](rnav::prl_plot_t& p) { p.course_rad = 1e6; })),
             Catch::Contains("azimuth 1000000 rad"));
  // A nav solution's time of validity is not bound by its batch's window (that is its arrival,
  // link_utime), so a flipped bit there needs its own checks: a time of validity after the
  // arrival or more than 10 s before it (bit 40: 12.7 days), and one out of order (bit 20:
  // 1.05 s, the paper's nav solutions are 1 s apart). Was: plots dropped without a word.
  auto with_nav = [&](const std::function<void(rnav::nav_solution_t&)>& change) {
    auto v = ev;
    std::size_t i = 0;
    nav_batch_t b;
    for (int w = 1; b.solutions.empty(); ++w) b = decode<nav_batch_t>(v[i = find_batch<nav_batch_t>(v, ch::kNav, 1, 1, w)]);
    INFO("window " << b.header.window);
    change(b.solutions[0]);
    v[i] = encode(ch::kNav, b);
    return v;
  };
  CHECK_THAT(log_error("nav40.lcmlog", with_nav([](rnav::nav_solution_t& n) { n.utime ^= std::int64_t{1} << 40; })),
             Catch::Contains("NAV_SOLUTION, realization 1, window 1") && Catch::Contains("time of validity"));
  CHECK_THAT(log_error("nav20.lcmlog", with_nav([](rnav::nav_solution_t& n) { n.utime ^= std::int64_t{1} << 20; })),
             Catch::Contains("nav solution") && Catch::Contains("not after the previous"));

  // The same layer behind the CSV reader: a nav header with latitude and longitude swapped, an
  // observer at latitude 95, a range of 1e200 m, a time of 1e300 s.
  const PrlFlightData ref = read_prl_lcm_log(paper_log(), realization(1));
  auto csv_error = [&](const std::string& name, const std::function<void(const fs::path&)>& damage) {
    const fs::path f = d / name;
    ref.write_folder(f.string());
    damage(f);
    return error_of([&] { PrlFlightData::read_folder(f.string()); });
  };
  auto replace_first = [](const fs::path& file, const std::string& from, const std::string& to) {
    std::string text = slurp(file);
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
  };
  CHECK_THAT(csv_error("swapped", [&](const fs::path& f) { replace_first(f / "nav.csv", "t_s,lat_deg,lon_deg", "t_s,lon_deg,lat_deg"); }),
             Catch::Contains("nav.csv lat_deg and nav.csv lon_deg look swapped") && Catch::Contains("km with latitude and longitude swapped"));
  CHECK_THAT(csv_error("lat95", [&](const fs::path& f) {
               std::string text = slurp(f / "nav.csv");
               const auto row = text.find('\n') + 1, c1 = text.find(',', row) + 1, c2 = text.find(',', c1);
               text.replace(c1, c2 - c1, "95");
               std::ofstream(f / "nav.csv", std::ios::binary | std::ios::trunc) << text;
             }),
             Catch::Contains("nav.csv:2") && Catch::Contains("latitude/longitude out of range"));
  CHECK_THAT(csv_error("range", [&](const fs::path& f) {
               std::string text = slurp(f / "radar.csv");
               const auto row = text.find('\n') + 1, c1 = text.find(',', row) + 1, c2 = text.find(',', c1);
               text.replace(c1, c2 - c1, "1e200");
               std::ofstream(f / "radar.csv", std::ios::binary | std::ios::trunc) << text;
             }),
             Catch::Contains("radar plot 0") && Catch::Contains("range 1e+200 m outside"));
  CHECK_THAT(csv_error("time", [&](const fs::path& f) {
               std::string text = slurp(f / "nav.csv");
               text += "1e300,48.1,16.5,300\n";
               std::ofstream(f / "nav.csv", std::ios::binary | std::ios::trunc) << text;
             }),
             Catch::Contains("time 1e+300 s"));
}

TEST_CASE("lcm log azimuth-only: the log gives exactly what the simulation published and the observer is the nav solution",
          "[lcm_log][uav]") {
  const fs::path d = scratch("uav");
  const std::string log = (d / "uav.lcmlog").string();
  const std::int64_t seed = 3;
  REQUIRE(export_lcm_log(kUav, {}, seed, 1, log) == 0);
  std::string summary;
  const AzimuthData a = read_uav_lcm_log(log, realization(0), &summary);
  INFO(summary);

  // Reference: the same simulation, collected straight from the bus (no log in between).
  const UavScenario sc = UavScenario::load(kUav);
  InprocBus bus;
  AzimuthData ref;
  std::vector<GeoSample> true_uav;
  auto t_of = [&](std::int64_t u) { return (u - sc.runner.epoch_utime) * 1e-6; };
  bus.subscribe<observer_batch_t>(ch::kUavNav, [&](const observer_batch_t& b) {
    for (const auto& s : b.states) ref.observer.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
  });
  bus.subscribe<observer_batch_t>(ch::kTruthUav, [&](const observer_batch_t& b) {
    for (const auto& s : b.states) true_uav.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, s.h_m}});
  });
  bus.subscribe<bearing_batch_t>(ch::kUavBearing, [&](const bearing_batch_t& b) {
    for (const auto& x : b.bearings) {
      if (ref.frames.empty() || ref.frames.back().t_s != t_of(x.utime)) ref.frames.push_back({t_of(x.utime), {}});
      ref.frames.back().bearings_rad.push_back(x.bearing_rad);
    }
  });
  bus.subscribe<target_truth_batch_t>(ch::kTruthTarget, [&](const target_truth_batch_t& b) {
    for (const auto& s : b.states) ref.truth.push_back({t_of(s.utime), {s.lat_deg, s.lon_deg, 0.0}});
  });
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TargetNode>(bus, sc.target, sc.sensor.period_s, sc.context()));
  nodes.push_back(make_uav_node(bus, sc));
  REQUIRE(run_inproc_nodes(bus, nodes, sc.runner, sc.sensor.period_s, sc.duration_s, 1, seed).exit_code == 0);

  REQUIRE(ref.frames.size() >= 10);
  REQUIRE(a.observer.size() == ref.observer.size());
  REQUIRE(a.frames.size() == ref.frames.size());
  REQUIRE(a.truth.size() == ref.truth.size());
  for (std::size_t i = 0; i < a.observer.size(); ++i) {
    CHECK(a.observer[i].t_s == ref.observer[i].t_s);
    CHECK(a.observer[i].g.lat_deg == ref.observer[i].g.lat_deg);
    CHECK(a.observer[i].g.lon_deg == ref.observer[i].g.lon_deg);
    CHECK(a.observer[i].g.h_m == ref.observer[i].g.h_m);
  }
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    CHECK(a.frames[i].t_s == ref.frames[i].t_s);
    CHECK(a.frames[i].bearings_rad == ref.frames[i].bearings_rad);
  }
  for (std::size_t i = 0; i < a.truth.size(); ++i) {
    CHECK(a.truth[i].g.lat_deg == ref.truth[i].g.lat_deg);
    CHECK(a.truth[i].g.lon_deg == ref.truth[i].g.lon_deg);
  }
  // The observer is the UAV's navigation solution, not its true state (which differs).
  REQUIRE(true_uav.size() == a.observer.size());
  double max_diff_m = 0;
  for (std::size_t i = 0; i < a.observer.size(); ++i)
    max_diff_m = std::max(max_diff_m, std::abs(a.observer[i].g.lat_deg - true_uav[i].g.lat_deg) * 111e3);
  CHECK(max_diff_m > 0.5);
  // Through the CSV format too, the diagnosis is the same.
  a.write_folder((d / "csv").string());
  const auto r1 = diagnose_uav(a, UavDiagnoseOptions{});
  const auto r2 = diagnose_uav(AzimuthData::read_folder((d / "csv").string()), UavDiagnoseOptions{});
  INFO("r1\n" << r1.text() << "\nr2\n" << r2.text());
  REQUIRE(r1.effects.size() == r2.effects.size());
  for (std::size_t i = 0; i < r1.effects.size(); ++i) CHECK(r1.effects[i].name == r2.effects[i].name);
  // A UAV log read as radar data: the scenario kind is named.
  CHECK_THAT(error_of([&] { read_prl_lcm_log(log, realization(0)); }), Catch::Contains("holds a 'uav' run"));
}

TEST_CASE("lcm log azimuth-only: effects hidden in the UAV simulation are found from its log",
          "[lcm_log][uav][diagnose]") {
  // The simulator injects the catalogue (sensor_effects.*, target.manoeuvres); the diagnosis of
  // its log must name them. Magnitudes are 3-5x the detection limits of this geometry (README).
  const fs::path d = scratch("uav_fx");
  auto find = [](const DiagnoseReport& r, const std::string& n) -> const EffectResult* {
    for (const auto& e : r.effects)
      if (e.name == n) return &e;
    return nullptr;
  };
  SECTION("bias and noise scale, with truth") {
    const std::string log = (d / "bias.lcmlog").string();
    REQUIRE(export_lcm_log(kUav, {"sensor_effects.bearing_bias_rad=0.004", "sensor_effects.noise_scale=1.5"}, 11, 1,
                           log) == 0);
    const auto r = diagnose_uav(read_uav_lcm_log(log, realization(0)), UavDiagnoseOptions{});
    INFO(r.text());
    const EffectResult* e = find(r, "bearing_bias");
    if (e) {
      CHECK(std::abs(e->estimate[0] - 0.004) <= 3 * e->stderr_[0]);
    } else {  // circling: the bias and a time offset are nearly the same regressor
      e = find(r, "time_offset");
      REQUIRE(e != nullptr);
      CHECK(std::find(e->confounded_with.begin(), e->confounded_with.end(), "bearing_bias") != e->confounded_with.end());
    }
    const EffectResult* ns = find(r, "noise_scale");
    REQUIRE(ns != nullptr);
    // the measured scatter also holds the UAV nav error (0.3 m at ~300 m: 1 mrad, 0.06 deg)
    const double expect = std::hypot(1.5 * 0.5, 0.3 / 300 / kDegToRad) / 0.5;
    CHECK(std::abs(ns->estimate[0] - expect) <= 3 * ns->stderr_[0]);
    CHECK(r.gain.at("bearing").extended_rms < r.gain.at("bearing").nominal_rms);
  }
  SECTION("a manoeuvre, without truth") {
    const std::string log = (d / "man.lcmlog").string();
    // a 30 deg turn at 3 deg/s from t = 60 s: the velocity changes by 2 sin(15 deg) = 0.52 m/s
    REQUIRE(export_lcm_log(kUav, {"target.manoeuvres=[[60,10,3,0]]"}, 12, 1, log) == 0);
    UavDiagnoseOptions o;
    o.ignore_truth = true;
    const auto r = diagnose_uav(read_uav_lcm_log(log, realization(0)), o);
    INFO(r.text());
    const EffectResult* e = find(r, "target_maneuver");
    REQUIRE(e != nullptr);
    // the turn lasts 10 s; a single velocity step fits it best near its middle (65 s)
    CHECK(std::abs(e->estimate[0] - 65) <= 5 + 2 * e->stderr_[0]);
    CHECK(r.gain.at("truth_position_m").extended_rms < r.gain.at("truth_position_m").nominal_rms);
  }
}
