#include "test/fuzz/fuzz_folder.hpp"
#include "test/fuzz/fuzz_target.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rnav::fuzz {

const std::string& scratch_dir() {
  static const std::string dir = [] {
    std::string t = (std::filesystem::temp_directory_path() / "rnav_fuzz.XXXXXX").string();
    if (!::mkdtemp(t.data())) throw std::runtime_error("fuzz: cannot create a scratch folder");
    return t;
  }();
  return dir;
}

std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = scratch_dir() + "/" + name;
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!f) throw std::runtime_error("fuzz: cannot write " + path);
  return path;
}

}  // namespace rnav::fuzz

// libFuzzer's entry point (and the driver's): a clean exception is a pass.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    rnav::fuzz::run_one(data, size);
  } catch (const std::exception&) {
  }
  return 0;
}

namespace rnav::fuzz {

std::string write_folder(const std::string& sub, const std::vector<std::string>& names, const std::uint8_t* data,
                         std::size_t size) {
  const std::string dir = scratch_dir() + "/" + sub;
  std::filesystem::create_directories(dir);
  std::size_t start = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::size_t end = start;
    while (end < size && data[end] != 0) ++end;
    const std::size_t from = std::min(start, size);
    write_scratch(sub + "/" + names[k], data + from, std::min(end, size) - from);
    start = end + 1;
  }
  return dir;
}

}  // namespace rnav::fuzz
