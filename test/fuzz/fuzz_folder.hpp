// Targets that read a folder of files: the input is the files' contents in a fixed order,
// separated by NUL bytes (missing parts are empty files; a part beyond the names is ignored).
#pragma once

#include "test/fuzz/fuzz_target.hpp"

#include <string>
#include <vector>

namespace rnav::fuzz {

/// Write the parts of `data` as scratch_dir()/sub/names[i]; returns the folder.
std::string write_folder(const std::string& sub, const std::vector<std::string>& names, const std::uint8_t* data,
                         std::size_t size);

}  // namespace rnav::fuzz
