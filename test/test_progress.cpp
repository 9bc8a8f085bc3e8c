// Unit tests of sim/clock/progress.hpp: a bar redrawn in place on a terminal, plain lines per
// 10 % otherwise.
#include "progress.hpp"

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
