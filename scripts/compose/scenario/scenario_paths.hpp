// The rule for a file path held by a scenario key: a relative path in the file is relative to
// the file's directory; one given by an override (--set KEY=...) is relative to the working
// directory, like any argument. Every scenario kind resolves its paths with it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rnav {

/// `path` (the value of scenario key `key` of scenario file `file`, with `overrides` applied)
/// made absolute by the rule above; "" and absolute paths unchanged.
inline std::string resolve_scenario_path(const std::string& path, const std::string& key, const std::string& file,
                                         const std::vector<std::string>& overrides) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  bool from_override = false;
  for (const auto& o : overrides)
    if (o.rfind(key + "=", 0) == 0) from_override = true;
  const std::filesystem::path base = from_override ? std::filesystem::current_path() : std::filesystem::absolute(file).parent_path();
  return (base / path).lexically_normal().string();
}

}  // namespace rnav
