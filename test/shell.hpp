// Shell helpers of the tests that run the project's scripts and programs (integration, MPI):
// a command's exit status and output, a file's bytes. RNAV_SOURCE_DIR and RNAV_BINARY_DIR come
// from CMake.
#pragma once

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
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

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// A fresh directory per test under the build (ctest may run tests in parallel).
inline std::filesystem::path scratch(const std::string& name) {
  const auto d = std::filesystem::path(RNAV_BINARY_DIR) / "test_scratch" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace rnav_test
