// Shell helpers of the tests that run the project's scripts and programs (integration, MPI,
// free-running, Python log reader): a command's exit status and output, a file's bytes (from
// test_support.hpp). RNAV_SOURCE_DIR and RNAV_BINARY_DIR come from CMake.
#pragma once

#include "test/test_support.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace rnav_test {

struct Result {
  int status = -1;
  std::string output;  // stdout and stderr
};

/// Run `cmd` under sh with RNAV_BUILD set to this build; its status (128 + signal if killed).
inline Result sh(const std::string& cmd) {
  Result r;
  const std::string full = "RNAV_BUILD='" + std::string(RNAV_BINARY_DIR) + "' " + cmd + " 2>&1";
  FILE* p = popen(full.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return r;
}

/// The output (stdout and stderr) of `cmd` run as sh() does; the test stops unless it exits 0.
inline std::string sh_ok(const std::string& cmd) {
  const Result r = sh(cmd);
  INFO(cmd << "\n" << r.output);
  REQUIRE(r.status == 0);
  return r.output;
}

/// A fresh directory per test under the build (ctest may run tests in parallel).
inline std::filesystem::path scratch(const std::string& name) {
  return fresh_dir(std::filesystem::path(RNAV_BINARY_DIR) / "test_scratch" / name);
}

}  // namespace rnav_test
