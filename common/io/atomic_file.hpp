// Results are never left half-written, and a user's files are never overwritten by surprise:
// files are written to a hidden temporary created exclusively (never through a planted link),
// checked to the last byte (a full disk is an error naming the file), synced, then renamed into
// place; an output folder is only written into if it is empty or an earlier output.
#pragma once

#include <string>

namespace rnav {

/// The marker file that makes a folder an output of this project (prepare_output_dir).
inline constexpr const char* kOutputMarker = ".rnav-output";

/// Write `text` to dir/name via dir/.name.partial and an atomic rename. The partial file is
/// created with O_CREAT|O_EXCL|O_NOFOLLOW after removing any stale one (unlink removes a link,
/// never its target). Throws std::runtime_error naming the file and the system's reason on any
/// failure (open, short write, ENOSPC, fsync, close, rename).
void write_file_atomic(const std::string& dir, const std::string& name, const std::string& text);
/// The same for a path (its folder: the path's parent, or ".").
void write_file_atomic(const std::string& path, const std::string& text);

/// A file written in pieces with write_file_atomic's guarantees (which uses it): dir/.name.partial
/// is created at construction (exclusively, never through a link), append() adds to it (a short
/// write or full disk throws naming the file), commit() syncs it and renames it to dir/name.
/// Destroyed without commit(), it closes and removes the partial file: no half-written result.
class AtomicFileWriter {
 public:
  AtomicFileWriter(const std::string& dir, const std::string& name);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  void append(const std::string& text);
  void commit();

 private:
  void abandon(const std::string& what, int err);  // close, remove the partial file, throw
  std::string tmp_, dst_;
  int fd_ = -1;
};

/// Make `dir` ready to receive a program's outputs without destroying anything of the user's:
/// create it if absent; accept it if empty or if it holds kOutputMarker (an earlier output);
/// otherwise throw ConfigError naming the folder and one of its files, unless `force`. Writes the
/// marker. `option` names the command-line option in the message (e.g. "--out").
void prepare_output_dir(const std::string& dir, bool force, const std::string& option = "--out");

/// printf("%.*f") as a string.
std::string fixed(double x, int prec = 6);
/// printf("%.*g") as a string: `digits` significant digits.
std::string significant(double x, int digits);

}  // namespace rnav
