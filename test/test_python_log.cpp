// The Python reader of LCM logs (loggers/rnav_lcmlog.py, through scripts/rnav_log2csv) against
// the C++ side: the same log, decoded by LcmEventReader and the C++ types, must give every value
// of the CSVs exactly (full double precision: the CSV holds Python's shortest round-trip text),
// in the same order; a corrupt log is an error naming the byte offset, and writes nothing.
#include "lcm_event_reader.hpp"
#include "lcm_log_export.hpp"

#include "batch_decode.hpp"

#include <rnav/nav_batch_t.hpp>
#include <rnav/prl_bias_batch_t.hpp>
#include <rnav/prl_plot_batch_t.hpp>

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

const std::string kPaper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("rnav_test_py_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Exit status and output (stdout and stderr) of a shell command.
std::pair<int, std::string> sh(const std::string& cmd) {
  std::string out;
  FILE* p = popen(("RNAV_BUILD='" + std::string(RNAV_BINARY_DIR) + "' " + cmd + " 2>&1").c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int st = pclose(p);
  REQUIRE(WIFEXITED(st));
  return {WEXITSTATUS(st), out};
}

// A CSV as header -> column of text cells.
std::map<std::string, std::vector<std::string>> read_csv(const fs::path& f) {
  std::ifstream in(f);
  REQUIRE(in.good());
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<std::string>> cols;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::size_t i = 0;
    for (std::string c; std::getline(ls, c, ','); ++i) {
      REQUIRE(i < names.size());
      cols[names[i]].push_back(c);
    }
  }
  return cols;
}

double num(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  REQUIRE(*end == '\0');
  return x;
}

const std::string kLog2csv = std::string(RNAV_SOURCE_DIR) + "/scripts/rnav_log2csv ";

}  // namespace

TEST_CASE("python log reader: every value of a paper log equals the C++ decode", "[python][lcm_log]") {
  const fs::path d = scratch("values");
  const std::string log = (d / "run.lcmlog").string();
  REQUIRE(export_lcm_log(kPaper, {"snsins.dropouts=[[100,130]]"}, 3, 2, log) == 0);
  const auto [st, out] = sh(kLog2csv + log + " --out " + (d / "csv").string());
  INFO(out);
  REQUIRE(st == 0);
  const auto apoi = read_csv(d / "csv" / "PRL_APOI.csv"), nav = read_csv(d / "csv" / "NAV_SOLUTION.csv"),
             bias = read_csv(d / "csv" / "PRL_BIAS.csv");
  std::size_t ia = 0, in = 0, ib = 0;
  LcmEventReader r(log);
  LcmEvent e;
  while (r.next(e)) {
    const int size = static_cast<int>(e.data.size());
    if (e.channel == "PRL_APOI") {
      prl_plot_batch_t b;
      REQUIRE(decode_batch(e.data.data(), size, b));
      for (const auto& p : b.plots) {
        REQUIRE(ia < apoi.at("range_m").size());
        CHECK(num(apoi.at("realization")[ia]) == b.header.realization);
        CHECK(num(apoi.at("window")[ia]) == b.header.window);
        CHECK(num(apoi.at("log_event")[ia]) == e.eventnum);
        CHECK(std::stoll(apoi.at("utime")[ia]) == p.utime);
        CHECK(std::stoll(apoi.at("plot_id")[ia]) == p.plot_id);
        CHECK(num(apoi.at("range_m")[ia]) == p.range_m);
        CHECK(num(apoi.at("course_rad")[ia]) == p.course_rad);
        CHECK(num(apoi.at("glide_rad")[ia]) == p.glide_rad);
        ++ia;
      }
    } else if (e.channel == "NAV_SOLUTION") {
      nav_batch_t b;
      REQUIRE(decode_batch(e.data.data(), size, b));
      for (const auto& s : b.solutions) {
        REQUIRE(in < nav.at("lat_deg").size());
        CHECK(std::stoll(nav.at("link_utime")[in]) == s.link_utime);
        CHECK(num(nav.at("lat_deg")[in]) == s.lat_deg);
        CHECK(num(nav.at("lon_deg")[in]) == s.lon_deg);
        CHECK(num(nav.at("h_m")[in]) == s.h_m);
        for (int k = 0; k < 3; ++k) CHECK(num(nav.at("v_N_" + std::to_string(k))[in]) == s.v_N[k]);
        ++in;
      }
    } else if (e.channel == "PRL_BIAS") {
      prl_bias_batch_t b;
      REQUIRE(decode_batch(e.data.data(), size, b));
      for (const auto& x : b.estimates) {
        REQUIRE(ib < bias.at("utime").size());
        for (int k = 0; k < 3; ++k) {
          CHECK(num(bias.at("eta_" + std::to_string(k))[ib]) == x.eta[k]);
          CHECK(num(bias.at("var_" + std::to_string(k))[ib]) == x.var[k]);
        }
        ++ib;
      }
    }
  }
  CHECK(ia > 900);  // two flights of about 500 plots
  // The module's numpy tables: as many rows, the same values (summed: numpy's pairwise order
  // against the C++ sequence's differs by rounding only, far below 1e-12 relative).
  double sum = 0;
  for (const auto& x : apoi.at("range_m")) sum += num(x);
  const auto [pst, pout] = sh("/usr/bin/python3 -c \"import sys; sys.path.insert(0, '" + std::string(RNAV_SOURCE_DIR) +
                              "/loggers'); import rnav_lcmlog as r; t = r.tables('" + log +
                              "')['PRL_APOI']; print(len(t['range_m']), repr(float(t['range_m'].sum())))\"");
  INFO(pout);
  REQUIRE(pst == 0);
  std::istringstream ps(pout);
  std::size_t rows = 0;
  double psum = 0;
  ps >> rows >> psum;
  CHECK(rows == apoi.at("range_m").size());
  CHECK(std::abs(psum - sum) <= 1e-12 * sum);
  CHECK(ia == apoi.at("range_m").size());
  CHECK(in == nav.at("lat_deg").size());
  CHECK(ib == bias.at("utime").size());
}

TEST_CASE("python log reader: a corrupt log is an error naming where, and writes nothing", "[python][lcm_log][input]") {
  const fs::path d = scratch("corrupt");
  const std::string good = (d / "good.lcmlog").string();
  REQUIRE(export_lcm_log(kPaper, {}, 3, 1, good) == 0);
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto variant = [&](const std::string& name, std::string b, const std::string& expected) {
    const fs::path f = d / (name + ".lcmlog"), o = d / (name + "_csv");
    std::ofstream(f, std::ios::binary) << b;
    const auto [st, out] = sh(kLog2csv + f.string() + " --out " + o.string());
    INFO(name << ": " << out);
    CHECK(st == 1);
    CHECK(out.find("rnav_log2csv: error: " + f.string()) != std::string::npos);
    CHECK(out.find(expected) != std::string::npos);
    CHECK(!fs::exists(o));
  };
  variant("truncated", bytes.substr(0, bytes.size() - 5), "runs past the end of the file");
  std::string sync = bytes;
  sync[0] = '\x00';
  variant("sync", sync, "byte 0: no LCM sync word");
  std::string huge = bytes;  // the first event's data length (bytes 24..27) claims 2^31 - 1
  huge[24] = '\x7f', huge[25] = huge[26] = huge[27] = '\xff';
  variant("huge", huge, "data length 2147483647 runs past the end");
  // A message with a fingerprint of no project type: the first event's first data byte.
  std::string foreign = bytes;
  const std::size_t first_data = 28 + static_cast<unsigned char>(bytes[23]);
  foreign[first_data] = static_cast<char>(foreign[first_data] ^ 0x55);
  variant("foreign", foreign, "is no project type");
}
