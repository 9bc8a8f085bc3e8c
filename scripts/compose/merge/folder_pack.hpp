// A shard's output folder as one byte string, to move it between MPI ranks (or hosts) and
// write it out again: the folder's regular files whose names do not start with '.', in name
// order, as "rnav-folder-pack 1\n" then per file "NAME\nSIZE\n" and SIZE bytes.
#pragma once

#include <string>

namespace rnav {

/// Pack dir's files. Throws std::runtime_error naming a file that cannot be read.
std::string pack_folder(const std::string& dir);
/// Write a pack's files into dir (created if absent). Throws std::invalid_argument naming
/// `what` on a malformed pack (bad header, a name with '/' or "..", a size past the end).
void unpack_folder(const std::string& pack, const std::string& dir, const std::string& what);

}  // namespace rnav
