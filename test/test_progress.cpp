// Unit tests of sim/clock/progress.hpp: a bar redrawn in place on a terminal, plain lines per
// 10 % otherwise.
#include "sim/clock/progress.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// What a ProgressBar writes for `total` realizations finished one by one, 0.1 s apart.
std::string output(bool redraw, int total) {
  char* buf = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buf, &size);
  REQUIRE(f != nullptr);
  {
    rnav::ProgressBar bar("ensemble", f, redraw);
    for (int done = 0; done <= total; ++done) bar.update(done, total, 0, 0.1 * done);
    bar.update(total, total, 0, 0.1 * total + 1);  // a repeated final report adds nothing
  }
  std::fclose(f);
  std::string s(buf, size);
  std::free(buf);
  return s;
}

}  // namespace

TEST_CASE("progress off a terminal: one plain line at 0 % and per further 10 %, no control characters",
          "[progress]") {
  const std::string s = output(false, 500);
  CHECK(s.find('\r') == std::string::npos);
  CHECK(std::count(s.begin(), s.end(), '\n') == 11);
  CHECK(s.find("ensemble 0/500 (  0 %)") == 0);
  CHECK(s.find("ensemble 250/500 ( 50 %)") != std::string::npos);
  CHECK(s.find("ensemble 500/500 (100 %)  50.0 s elapsed  ETA 0.0 s") != std::string::npos);
  // Fewer realizations than deciles: a line per realization, never more.
  const std::string few = output(false, 3);
  CHECK(std::count(few.begin(), few.end(), '\n') == 4);
}

TEST_CASE("progress on a terminal: redrawn in place, one line break at the end", "[progress]") {
  const std::string s = output(true, 20);
  CHECK(std::count(s.begin(), s.end(), '\r') == 21);
  CHECK(std::count(s.begin(), s.end(), '\n') == 1);
  CHECK(s.back() == '\n');
  CHECK(s.find("] 20/20") != std::string::npos);
}

TEST_CASE("progress inside a realization: the share done, the sim time, and no ETA before anything is done",
          "[progress]") {
  char* buf = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buf, &size);
  REQUIRE(f != nullptr);
  {
    rnav::ProgressBar bar("realtime", f, false);
    bar.update(0, 1, 0, 0.0);
    // one realization of 50 s in 50 windows, one a second of wall time
    for (int w = 1; w < 50; ++w) bar.update(w / 50.0, 1, 0, 1.0 * w, "sim " + std::to_string(w) + "/50 s");
    bar.update(1, 1, 0, 50.0);
  }
  std::fclose(f);
  const std::string s(buf, size);
  std::free(buf);
  INFO(s);
  CHECK(s.find("realtime 0/1 (  0 %)  0.0 s elapsed  ETA unknown") == 0);
  // at 10 s of 50: 0.20 done, 10 s elapsed, 40 s to go
  CHECK(s.find("realtime 0.10/1 ( 10 %)  sim 5/50 s  5.0 s elapsed  ETA 45.0 s") != std::string::npos);
  CHECK(s.find("realtime 0.20/1 ( 20 %)  sim 10/50 s  10.0 s elapsed  ETA 40.0 s") != std::string::npos);
  CHECK(s.find("realtime 1/1 (100 %)  50.0 s elapsed  ETA 0.0 s") != std::string::npos);
  CHECK(std::count(s.begin(), s.end(), '\n') == 11);
}
