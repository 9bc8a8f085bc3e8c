#include "scripts/compose/merge/folder_pack.hpp"

#include "common/io/atomic_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rnav {

namespace {
constexpr const char* kHeader = "rnav-folder-pack 1\n";
}

std::string pack_folder(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.empty() || n.front() == '.' || !e.is_regular_file()) continue;
    names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  std::string out = kHeader;
  for (const auto& n : names) {
    std::ifstream f(dir + "/" + n, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    if (!f || f.bad()) throw std::runtime_error(dir + "/" + n + ": cannot be read");
    const std::string body = s.str();
    out += n + "\n" + std::to_string(body.size()) + "\n";
    out += body;
  }
  return out;
}

void unpack_folder(const std::string& pack, const std::string& dir, const std::string& what) {
  const std::string header = kHeader;
  if (pack.compare(0, header.size(), header) != 0) throw std::invalid_argument(what + ": not a folder pack");
  std::filesystem::create_directories(dir);
  std::size_t at = header.size();
  const auto line = [&](const char* field) {
    const auto nl = pack.find('\n', at);
    if (nl == std::string::npos) throw std::invalid_argument(what + ": the pack ends inside a file's " + field);
    std::string s = pack.substr(at, nl - at);
    at = nl + 1;
    return s;
  };
  while (at < pack.size()) {
    const std::string name = line("name");
    if (name.empty() || name.find('/') != std::string::npos || name == "." || name == ".." || name.front() == '.')
      throw std::invalid_argument(what + ": bad file name '" + name + "'");
    const std::string size_text = line("size");
    std::size_t used = 0;
    unsigned long long size = 0;
    try {
      size = std::stoull(size_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != size_text.size() || size > pack.size() - at)
      throw std::invalid_argument(what + ": file '" + name + "': bad size '" + size_text + "'");
    write_file_atomic(dir, name, pack.substr(at, size));
    at += size;
  }
}

}  // namespace rnav
