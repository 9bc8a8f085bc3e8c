// File helpers shared by the tests: a fresh, empty scratch folder, and a file's bytes.
// Header-only; needs nothing from CMake (the shell helpers, which do, are in shell.hpp).
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rnav_test {

/// The folder `d`, emptied and created afresh (a test's scratch folder).
inline std::filesystem::path fresh_dir(const std::filesystem::path& d) {
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// The bytes of file `p` ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace rnav_test
