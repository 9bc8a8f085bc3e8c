// The Python reader of LCM logs (scripts/rnav/lcmlog.py, through scripts/rnav_log2csv) against
// the C++ reader (LcmLogStreams, estimators/diagnosis/io: the checked batches of each realization's last
// attempt): every value of every sample of every data channel, in order, exactly (full double
// precision: the CSV holds Python's shortest round-trip text); a sample-wire log gives the same
// tables as the batch-wire log of the same run; the numpy tables hold the CSV's values; a
// corrupt log, or one that lost a message, is an error naming where, and writes nothing.
// ctest names: python.log_reader, python.sample_wire, python.numpy_tables, python.corrupt_log,
// python.log2csv.
#include "common/node/batch_decode.hpp"
#include "estimators/diagnosis/io/lcm_event_reader.hpp"
#include "scripts/compose/export/lcm_log_export.hpp"
#include "estimators/diagnosis/io/lcm_log_streams.hpp"
#include "test/shell.hpp"

#include <rnav/aircraft_truth_batch_t.hpp>
#include <rnav/bearing_batch_t.hpp>
#include <rnav/nav_batch_t.hpp>
#include <rnav/observer_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_error_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>
#include <rnav/target_truth_batch_t.hpp>
#include <rnav/tma_batch_t.hpp>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace rnav;
using rnav_test::sh;
using rnav_test::slurp;

namespace {

const std::string kPaper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";
const std::string kUav = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/uav.json";
const std::string kLog2csv = std::string(RNAV_SOURCE_DIR) + "/scripts/rnav_log2csv ";

fs::path scratch(const std::string& name) {
  return rnav_test::fresh_dir(fs::temp_directory_path() / ("rnav_test_py_" + name + "_" + std::to_string(::getpid())));
}

// One CSV line's cells (RFC 4180 quoting, as Python's csv module writes).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
    else if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) out.emplace_back();
    else out.back() += c;
  }
  return out;
}

// A CSV of rnav_log2csv: column names (the header: plain names, letters, digits and '_' only),
// units (from CHANNEL.units.json beside it, {unit, meaning} per column), rows of cells.
struct Csv {
  std::vector<std::string> names, units;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    FAIL("no column " << name);
    return 0;
  }
};

Csv read_csv(const fs::path& f) {
  std::ifstream in(f);
  REQUIRE(in.good());
  Csv c;
  std::string line;
  std::getline(in, line);
  for (const auto& h : cells(line)) {
    INFO(f.string() << ": column '" << h << "'");
    CHECK((!h.empty() && std::all_of(h.begin(), h.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; })));
    c.names.push_back(h);
  }
  fs::path up = f;
  up.replace_extension(".units.json");
  std::ifstream uin(up);
  REQUIRE(uin.good());
  const nlohmann::json units = nlohmann::json::parse(uin);
  REQUIRE(units.size() == c.names.size());
  for (const auto& n : c.names) {
    INFO(up.string() << ": column '" << n << "'");
    c.units.push_back(units.at(n).at("unit").get<std::string>());
    CHECK(!units.at(n).at("meaning").get<std::string>().empty());
  }
  while (std::getline(in, line)) {
    c.rows.push_back(cells(line));
    REQUIRE(c.rows.back().size() == c.names.size());
  }
  return c;
}

double number(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  REQUIRE((!text.empty() && *end == '\0'));
  return x;
}

// One CSV row against a C++ sample: every column named must hold the value exactly; counts the
// columns it compared, so that a test can require every column.
struct Row {
  const Csv& csv;
  std::size_t i;
  std::string where;
  std::set<std::string> seen;
  void operator()(const std::string& name, double v) { at(name, number(cell(name)) == v, v); }
  void operator()(const std::string& name, std::int64_t v) { at(name, cell(name) == std::to_string(v), v); }
  void operator()(const std::string& name, std::int32_t v) { (*this)(name, std::int64_t{v}); }
  void operator()(const std::string& name, std::int8_t v) { (*this)(name, std::int64_t{v}); }
  void operator()(const std::string& name, bool v) { at(name, cell(name) == (v ? "1" : "0"), v); }
  void operator()(const std::string& name, const std::string& v) { at(name, cell(name) == v, v); }
  template <class T, std::size_t N> void operator()(const std::string& name, const T (&a)[N]) {
    for (std::size_t k = 0; k < N; ++k) (*this)(name + "_" + std::to_string(k), a[k]);
  }
  const std::string& cell(const std::string& name) {
    seen.insert(name);
    return csv.rows.at(i).at(csv.col(name));
  }
  template <class V> void at(const std::string& name, bool ok, const V& v) {
    if (!ok) FAIL_CHECK(where << " row " << i << " column " << name << ": CSV '" << csv.rows[i][csv.col(name)]
                              << "', C++ " << v);
  }
};

void fields(Row& r, const aircraft_state_t& s) {
  r("utime", s.utime), r("p_TA_L", s.p_TA_L), r("v_A_L", s.v_A_L), r("lat_deg", s.lat_deg), r("lon_deg", s.lon_deg),
      r("h_m", s.h_m);
}
void fields(Row& r, const nav_solution_t& s) {
  r("utime", s.utime), r("link_utime", s.link_utime), r("lat_deg", s.lat_deg), r("lon_deg", s.lon_deg),
      r("h_m", s.h_m), r("v_N", s.v_N), r("sigma_pos_m", s.sigma_pos_m);
}
void fields(Row& r, const prl_plot_t& s) {
  r("utime", s.utime), r("plot_id", s.plot_id), r("range_m", s.range_m), r("course_rad", s.course_rad),
      r("glide_rad", s.glide_rad);
}
void fields(Row& r, const prl_error_t& s) {
  r("utime", s.utime), r("plot_id", s.plot_id), r("sys_range_m", s.sys_range_m), r("sys_course_rad", s.sys_course_rad),
      r("sys_glide_rad", s.sys_glide_rad), r("total_range_m", s.total_range_m),
      r("total_course_rad", s.total_course_rad), r("total_glide_rad", s.total_glide_rad);
}
void fields(Row& r, const prl_bias_estimate_t& s) {
  r("utime", s.utime), r("plot_id", s.plot_id), r("mode", s.mode), r("has_chi", s.has_chi), r("chi", s.chi),
      r("eta", s.eta), r("var", s.var), r("gain", s.gain);
}
void fields(Row& r, const target_state_t& s) {
  r("utime", s.utime), r("p_OT_F", s.p_OT_F), r("v_T_F", s.v_T_F), r("lat_deg", s.lat_deg), r("lon_deg", s.lon_deg);
}
void fields(Row& r, const observer_state_t& s) {
  r("utime", s.utime), r("p_OU_F", s.p_OU_F), r("v_U_F", s.v_U_F), r("lat_deg", s.lat_deg), r("lon_deg", s.lon_deg),
      r("h_m", s.h_m), r("sigma_pos_m", s.sigma_pos_m);
}
void fields(Row& r, const bearing_t& s) {
  r("utime", s.utime), r("frame_id", s.frame_id), r("bearing_rad", s.bearing_rad), r("sigma_rad", s.sigma_rad);
}
void fields(Row& r, const tma_estimate_t& s) {
  r("utime", s.utime), r("estimator", s.estimator), r("updated", s.updated), r("x", s.x), r("P", s.P), r("nis", s.nis);
}

// Every sample of a channel's batches in one realization against the CSV, from row `row` on.
template <class B, class V>
void compare(const LcmLogStreams& s, const std::string& channel, V B::*items, const Csv& csv, std::size_t& row) {
  for (const B* b : s.batches<B>(channel))
    for (const auto& x : b->*items) {
      REQUIRE(row < csv.rows.size());
      Row r{csv, row, channel, {}};
      r("realization", b->header.realization), r("attempt", b->header.attempt), r("window", b->header.window);
      r("window_utime_begin", b->header.utime_begin), r("window_utime_end", b->header.utime_end);
      fields(r, x);
      CHECK(r.seen.size() + 2 == csv.names.size());  // every column but log_event and log_utime
      ++row;
    }
}

// rnav_log2csv of `log` into `out`, which must succeed.
void log2csv(const std::string& log, const fs::path& out, const std::string& options = "") {
  const auto [st, text] = sh(kLog2csv + log + " --out " + out.string() + options);
  INFO(text);
  REQUIRE(st == 0);
}

// A CSV's text without its first two columns (log_event, log_utime: where the recorder put it).
std::string without_log_columns(const fs::path& f) {
  std::ifstream in(f);
  std::string line, out;
  while (std::getline(in, line)) {
    std::size_t k = 0;
    for (int c = 0; c < 2; ++c) k = line.find(',', k) + 1;
    out += line.substr(k) + "\n";
  }
  return out;
}

const std::vector<std::string> kPaperData = {"TRUTH_AIRCRAFT", "NAV_SOLUTION", "PRL_APOI",
                                             "TRUTH_PRL_ERROR", "PRL_TOI",      "PRL_BIAS"};

}  // namespace

TEST_CASE("log_reader", "[python][lcm_log]") {
  // Every value of every data channel equals the C++ reader's: a landing log of the processes
  // over LCM (scripts/run --lcm-log, lcm-logger), and in-process logs of a landing run (two
  // flights with a nav drop-out, the second repeated once: a lost batch) and of a UAV run.
  const fs::path d = scratch("values");
  struct Log {
    std::string file, scenario;
    std::vector<std::string> overrides, drops;
    bool lcm = false;  // recorded by scripts/run from the processes, else export_lcm_log
  };
  const std::vector<Log> logs = {
      // 100 s windows (the landing default is one per realization): window 2 exists to be dropped.
      {(d / "paper.lcmlog").string(), kPaper, {"snsins.dropouts=[[100,130]]", "runner.window_s=100"}, {"PRL_APOI:1:2:0"}},
      {(d / "uav.lcmlog").string(), kUav, {}, {}},
      {(d / "lcm.lcmlog").string(), kPaper, {}, {}, true}};
  for (const auto& log : logs) {
    if (log.lcm) {
      const auto [st, out] = sh(std::string(RNAV_SOURCE_DIR) + "/scripts/run paper --realizations 2 --seed 3 --lcm-log " +
                                log.file + " --out " + (d / "run").string());
      INFO(out);
      REQUIRE(st == 0);
    } else {
      REQUIRE(export_lcm_log(log.scenario, log.overrides, 3, 2, log.file, log.drops) == 0);
    }
    const fs::path out = log.file + ".csv";
    log2csv(log.file, out);
    std::map<std::string, Csv> csv;
    for (const auto& e : fs::directory_iterator(out))
      if (e.path().extension() == ".csv") csv[e.path().stem().string()] = read_csv(e.path());
    std::map<std::string, std::size_t> row;
    for (int r = 0; r < 2; ++r) {
      LcmLogStreams s;
      if (log.scenario == kPaper) {
        s.add_stream<aircraft_truth_batch_t>("TRUTH_AIRCRAFT"), s.add_stream<nav_batch_t>("NAV_SOLUTION");
        s.add_stream<prl_plot_batch_t>("PRL_APOI"), s.add_stream<prl_error_batch_t>("TRUTH_PRL_ERROR");
        s.add_stream<prl_plot_batch_t>("PRL_TOI"), s.add_stream<prl_bias_batch_t>("PRL_BIAS");
        s.read(log.file, r);
        if (!log.drops.empty()) CHECK(s.attempt() == (r == 1 ? 1 : 0));  // the drop repeated realization 1
        compare(s, "TRUTH_AIRCRAFT", &aircraft_truth_batch_t::states, csv.at("TRUTH_AIRCRAFT"), row["TRUTH_AIRCRAFT"]);
        compare(s, "NAV_SOLUTION", &nav_batch_t::solutions, csv.at("NAV_SOLUTION"), row["NAV_SOLUTION"]);
        compare(s, "PRL_APOI", &prl_plot_batch_t::plots, csv.at("PRL_APOI"), row["PRL_APOI"]);
        compare(s, "TRUTH_PRL_ERROR", &prl_error_batch_t::errors, csv.at("TRUTH_PRL_ERROR"), row["TRUTH_PRL_ERROR"]);
        compare(s, "PRL_TOI", &prl_plot_batch_t::plots, csv.at("PRL_TOI"), row["PRL_TOI"]);
        compare(s, "PRL_BIAS", &prl_bias_batch_t::estimates, csv.at("PRL_BIAS"), row["PRL_BIAS"]);
      } else {
        s.add_stream<target_truth_batch_t>("TRUTH_TARGET"), s.add_stream<observer_batch_t>("TRUTH_UAV");
        s.add_stream<observer_batch_t>("UAV_NAV"), s.add_stream<bearing_batch_t>("UAV_BEARING");
        s.add_stream<tma_batch_t>("UAV_TMA");
        s.read(log.file, r);
        compare(s, "TRUTH_TARGET", &target_truth_batch_t::states, csv.at("TRUTH_TARGET"), row["TRUTH_TARGET"]);
        compare(s, "TRUTH_UAV", &observer_batch_t::states, csv.at("TRUTH_UAV"), row["TRUTH_UAV"]);
        compare(s, "UAV_NAV", &observer_batch_t::states, csv.at("UAV_NAV"), row["UAV_NAV"]);
        compare(s, "UAV_BEARING", &bearing_batch_t::bearings, csv.at("UAV_BEARING"), row["UAV_BEARING"]);
        compare(s, "UAV_TMA", &tma_batch_t::estimates, csv.at("UAV_TMA"), row["UAV_TMA"]);
      }
    }
    // Each data channel's CSV has exactly the C++ reader's rows: none more, none fewer.
    for (const auto& [channel, n] : row) {
      INFO(log.file << " " << channel);
      CHECK(n == csv.at(channel).rows.size());
      CHECK(n > 400);  // two flights of several hundred samples each
    }
    CHECK(row.size() == (log.scenario == kPaper ? 6u : 5u));
    CHECK(csv.count("SIM_WINDOW") == 1);
  }
  // --all-attempts keeps realization 1's first attempt too: more rows, with attempt 0 in them.
  const fs::path all = d / "all";
  log2csv(logs[0].file, all, " --all-attempts --channels PRL_APOI");
  const Csv apoi = read_csv(d / "paper.lcmlog.csv" / "PRL_APOI.csv"), every = read_csv(all / "PRL_APOI.csv");
  std::size_t first_attempt = 0;
  for (const auto& r : every.rows)
    first_attempt += r[every.col("realization")] == "1" && r[every.col("attempt")] == "0";
  CHECK(first_attempt > 0);
  CHECK(every.rows.size() == apoi.rows.size() + first_attempt);
}

TEST_CASE("sample_wire", "[python][lcm_log]") {
  // runner.wire=sample (one message per sample, no message for an empty window): the same tables
  // as the batch run, every column but where the recorder put them; truth repeats itself from
  // one flight to the next and must not be taken for a resent copy.
  const fs::path d = scratch("wire");
  const std::string batch = (d / "batch.lcmlog").string(), sample = (d / "sample.lcmlog").string();
  REQUIRE(export_lcm_log(kPaper, {}, 4, 2, batch) == 0);
  REQUIRE(export_lcm_log(kPaper, {"runner.wire=sample"}, 4, 2, sample) == 0);
  log2csv(batch, d / "b");
  log2csv(sample, d / "s");
  for (const auto& channel : kPaperData) {
    INFO(channel);
    const std::string b = without_log_columns(d / "b" / (channel + ".csv"));
    CHECK(b == without_log_columns(d / "s" / (channel + ".csv")));
    CHECK(std::count(b.begin(), b.end(), '\n') > 900);
  }
  CHECK(read_csv(d / "s" / "TRUTH_AIRCRAFT.csv").rows.size() > read_csv(d / "s" / "PRL_APOI.csv").rows.size());
  // A sample message lost (the log's first PRL_APOI plot after window 0's grant): named by the
  // count the publisher's OK ack lists.
  std::string bytes = slurp(sample), cut;
  LcmEventReader r(sample);
  LcmEvent e;
  bool done = false;
  while (r.next(e)) {
    const auto end = static_cast<std::size_t>(e.offset) + 28 + e.channel.size() + e.data.size();
    if (!done && e.channel == "PRL_APOI") done = true;
    else cut += bytes.substr(static_cast<std::size_t>(e.offset), end - static_cast<std::size_t>(e.offset));
  }
  REQUIRE(done);
  const fs::path lost = d / "lost.lcmlog";
  std::ofstream(lost, std::ios::binary) << cut;
  const auto [st, out] = sh(kLog2csv + lost.string() + " --out " + (d / "lost").string());
  INFO(out);
  CHECK(st == 2);
  CHECK(out.find("PRL_APOI, realization 0, attempt 0, window 0: ") != std::string::npos);
  CHECK(out.find("the publisher's OK ack lists") != std::string::npos);
}

TEST_CASE("numpy_tables", "[python][lcm_log]") {
  // rnav.lcmlog.tables(): numpy columns holding exactly the CSV's values, numbers as numbers;
  // with LCM's Python module made unimportable.
  const fs::path d = scratch("numpy");
  const std::string log = (d / "run.lcmlog").string();
  REQUIRE(export_lcm_log(kUav, {}, 5, 1, log) == 0);
  log2csv(log, d / "csv");
  const fs::path script = d / "check.py";
  std::ofstream(script) << "import csv, sys\n"
                           "from urllib.parse import unquote  # text cells are percent-encoded (scripts/rnav/csvio.py)\n"
                           "sys.modules['lcm'] = None  # the generated types must not need LCM's module\n"
                           "from rnav import lcmlog as rnav_lcmlog\n"
                           "t = rnav_lcmlog.tables(sys.argv[1])\n"
                           "n = 0\n"
                           "for ch, cols in t.items():\n"
                           "    rows = list(csv.reader(open(sys.argv[2] + '/' + ch + '.csv')))\n"
                           "    names = [h.split(' [')[0] for h in rows[0]]\n"
                           "    assert names == list(cols), (ch, names)\n"
                           "    for j, (name, a) in enumerate(cols.items()):\n"
                           "        text = [r[j] for r in rows[1:]]\n"
                           "        if a.dtype.kind == 'f':\n"
                           "            ok = [float(x) for x in text] == a.tolist()\n"
                           "        elif a.dtype.kind in 'ib':\n"
                           "            ok = [int(x) for x in text] == a.astype('int64').tolist()\n"
                           "        else:\n"
                           "            ok = a.dtype.kind == 'U' and [unquote(x) for x in text] == a.tolist()\n"
                           "        assert ok, (ch, name, a.dtype)\n"
                           "        n += len(text)\n"
                           "print(t['UAV_TMA']['P_3_3'].dtype, t['UAV_TMA']['updated'].dtype, "
                           "t['UAV_TMA']['utime'].dtype, n)\n";
  // the checkout's own package, as ctest gives the python tests (PYTHONPATH)
  const auto [st, out] = sh("PYTHONPATH=" + std::string(RNAV_SOURCE_DIR) + "/scripts /usr/bin/python3 " + script.string() +
                            " " + log + " " + (d / "csv").string());
  INFO(out);
  REQUIRE(st == 0);
  std::istringstream os(out);
  std::string f, b, i;
  long n = 0;
  os >> f >> b >> i >> n;
  CHECK(f == "float64");
  CHECK(b == "bool");
  CHECK(i == "int64");
  CHECK(n > 10000);
}

TEST_CASE("corrupt_log", "[python][lcm_log][input]") {
  // Each a LogError naming the file and where, exit status 2, nothing written.
  const fs::path d = scratch("corrupt");
  const std::string good = (d / "good.lcmlog").string();
  REQUIRE(export_lcm_log(kPaper, {"runner.window_s=100"}, 3, 1, good) == 0);  // several windows: a batch well inside
  const std::string bytes = slurp(good);
  // The events' offsets and sizes, from the C++ reader.
  std::vector<LcmEvent> ev;
  {
    LcmEventReader r(good);
    for (LcmEvent e; r.next(e);) ev.push_back(e);
  }
  auto span = [&](std::size_t k) {
    return bytes.substr(static_cast<std::size_t>(ev[k].offset), 28 + ev[k].channel.size() + ev[k].data.size());
  };
  auto first_on = [&](const std::string& channel, std::size_t after = 0) {
    for (std::size_t k = after; k < ev.size(); ++k)
      if (ev[k].channel == channel) return k;
    FAIL("no " << channel);
    return std::size_t{0};
  };
  const std::size_t k = first_on("PRL_APOI", 3);  // a batch well inside the log
  const std::string at = ": byte " + std::to_string(ev[k].offset);
  auto variant = [&](const std::string& name, const std::string& b, const std::string& expected) {
    const fs::path f = d / (name + ".lcmlog"), o = d / (name + "_csv");
    std::ofstream(f, std::ios::binary) << b;
    const auto [st, out] = sh(kLog2csv + f.string() + " --out " + o.string());
    INFO(name << ": " << out);
    CHECK(st == 2);
    CHECK(out.rfind("rnav_log2csv: error: " + f.string(), 0) == 0);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
    CHECK(out.find(expected) != std::string::npos);
    CHECK(!fs::exists(o));
  };
  auto with = [&](std::size_t at_byte, const std::string& patch) {
    std::string b = bytes;
    b.replace(at_byte, patch.size(), patch);
    return b;
  };
  const auto off = static_cast<std::size_t>(ev[k].offset);
  variant("truncated", bytes.substr(0, bytes.size() - 5),
          ": byte " + std::to_string(ev.back().offset) + " (event " + std::to_string(ev.size() - 1) +
              " of the file): claims " + std::to_string(span(ev.size() - 1).size()) + " bytes, the file has " +
              std::to_string(span(ev.size() - 1).size() - 5) + " left: the log was cut");
  variant("sync", with(off, std::string("\xED\xA1\xDA\x02", 4)), at + " (event " + std::to_string(k) +
                                                                      " of the file): no sync word 0xEDA1DA01 (found 0xEDA1DA02)");
  variant("huge", with(off + 24, std::string("\x7f\xff\xff\xff", 4)), at + " (event " + std::to_string(k) +
                                                                          " of the file): claims 2147483");
  variant("channel_length", with(off + 20, std::string("\x00\x01\x00\x00", 4)), "channel name length 65536 outside [1, 256]");
  variant("event_number", with(off + 4, std::string(8, '\0')), "event number 0 after");
  // A fingerprint of no project type; a batch whose count says more than it holds.
  const auto data = off + 28 + ev[k].channel.size();
  variant("foreign", with(data, std::string(1, static_cast<char>(bytes[data] ^ 0x55))),
          "event " + std::to_string(ev[k].eventnum) + " (byte " + std::to_string(off) + ") on channel PRL_APOI: fingerprint ");
  variant("count", with(data + static_cast<std::size_t>(rnav::batch_count_offset()), std::string("\x00\x00\x7f\xff", 4)),
          "does not decode as rnav.prl_plot_batch_t");
  // A batch lost (the log skips it), and one sent twice with different contents (in the place of
  // a later acknowledgement, with its event number).
  prl_plot_batch_t batch;
  REQUIRE(decode_batch(ev[k].data.data(), static_cast<int>(ev[k].data.size()), batch));
  REQUIRE(batch.n > 0);
  variant("lost", bytes.substr(0, off) + bytes.substr(off + span(k).size()),
          "PRL_APOI, realization 0, attempt 0: window " + std::to_string(batch.header.window) + " is missing");
  const std::size_t ack = first_on("SIM_ACK", k + 1);
  const auto ack_off = static_cast<std::size_t>(ev[ack].offset);
  std::string twice = span(k);
  twice.replace(4, 8, bytes.substr(ack_off + 4, 8));
  twice.back() = static_cast<char>(twice.back() ^ 1);  // the last plot's glide angle, one bit
  variant("differs", bytes.substr(0, ack_off) + twice + bytes.substr(ack_off + span(ack).size()),
          "PRL_APOI, realization 0, attempt 0, window " + std::to_string(batch.header.window) + ": the batch of event " +
              std::to_string(ev[ack].eventnum) + " differs from the one of event " + std::to_string(ev[k].eventnum));
  // The first grant lost: the realization's windows do not start at 0.
  const std::size_t g = first_on("SIM_WINDOW");
  variant("grant", bytes.substr(0, static_cast<std::size_t>(ev[g].offset)) + bytes.substr(ev[g].offset + span(g).size()),
          "SIM_WINDOW, realization 0, attempt 0 (its last): the grant of window 0 is missing");
  // The log cut after a whole event: the realization did not complete.
  variant("cut", bytes.substr(0, off), "did not complete");
}

TEST_CASE("log2csv", "[python][lcm_log][input]") {
  // --out: refused if it holds someone else's files (left as they were), replaced if it is an
  // earlier output or with --force; a CSV per channel, its units in CHANNEL.units.json beside it.
  const fs::path d = scratch("out");
  const std::string log = (d / "run.lcmlog").string();
  REQUIRE(export_lcm_log(kPaper, {}, 3, 1, log) == 0);
  const fs::path out = d / "csv";
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine\n";
  const auto [st, text] = sh(kLog2csv + log + " --out " + out.string());
  CHECK(st == 2);
  CHECK(text == "rnav_log2csv: error: --out " + out.string() + ": the folder is not empty (it holds notes.txt) and "
                "is not an earlier output of this project (no .rnav-output): choose an empty or new folder, or add "
                "--force to replace it\n");
  CHECK(slurp(out / "notes.txt") == "mine\n");
  log2csv(log, out, " --force");
  CHECK(!fs::exists(out / "notes.txt"));
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(out)) files.insert(e.path().filename().string());
  std::set<std::string> expected = {".rnav-output"};
  for (const std::string c : {"SIM_WINDOW", "SIM_ACK", "SIM_SCENARIO"}) expected.insert({c + ".csv", c + ".units.json"});
  for (const auto& c : kPaperData) expected.insert({c + ".csv", c + ".units.json"});
  CHECK(files == expected);
  log2csv(log, out, " --channels PRL_APOI");  // an earlier output: replaced whole, no --force
  files.clear();
  for (const auto& e : fs::directory_iterator(out)) files.insert(e.path().filename().string());
  CHECK(files == std::set<std::string>{".rnav-output", "PRL_APOI.csv", "PRL_APOI.units.json"});
  const Csv apoi = read_csv(out / "PRL_APOI.csv");
  CHECK(apoi.units[apoi.col("range_m")] == "m");
  CHECK(apoi.units[apoi.col("course_rad")] == "rad");
  CHECK(apoi.units[apoi.col("utime")] == "us since Unix epoch");
  CHECK(apoi.units[apoi.col("window_utime_begin")] == "us since Unix epoch, sim time");
  CHECK(apoi.units[apoi.col("plot_id")].empty());
  // An array's units element by element where the .lcm lists one per element.
  log2csv(log, out, " --channels PRL_BIAS");
  const Csv bias = read_csv(out / "PRL_BIAS.csv");
  CHECK(bias.units[bias.col("eta_0")] == "m");
  CHECK(bias.units[bias.col("eta_1")] == "rad");
  CHECK(bias.units[bias.col("var_2")] == "rad^2");
  // A channel the log does not have: named, with the nearest one it has.
  const auto [st2, text2] = sh(kLog2csv + log + " --out " + (d / "x").string() + " --channels PRL_TOY");
  CHECK(st2 == 2);
  CHECK(text2.find("rnav_log2csv: error: channel(s) not in the log: PRL_TOY (did you mean 'PRL_TOI'?)") == 0);
  CHECK(!fs::exists(d / "x"));
}
