#include "common/io/atomic_file.hpp"

#include "common/io/config.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace rnav {

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& file, int err) {
  throw std::runtime_error("cannot " + what + " " + file + ": " + std::strerror(err));
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(const std::string& dir, const std::string& name)
    : tmp_(dir + "/." + name + ".partial"), dst_(dir + "/" + name) {
  if (::unlink(tmp_.c_str()) != 0 && errno != ENOENT) fail("remove the stale", tmp_, errno);
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd_ < 0) fail("create", tmp_, errno);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(tmp_.c_str());
  }
}

void AtomicFileWriter::abandon(const std::string& what, int err) {
  ::close(fd_);
  fd_ = -1;
  ::unlink(tmp_.c_str());
  fail(what, tmp_, err);
}

void AtomicFileWriter::append(const std::string& text) {
  if (fd_ < 0) throw std::logic_error("AtomicFileWriter: append to " + dst_ + " after commit");
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t w = ::write(fd_, text.data() + done, text.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) abandon("write", w < 0 ? errno : ENOSPC);
    done += static_cast<std::size_t>(w);
  }
}

void AtomicFileWriter::commit() {
  if (fd_ < 0) throw std::logic_error("AtomicFileWriter: " + dst_ + " committed twice");
  if (::fsync(fd_) != 0) abandon("sync", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp_.c_str());
    fail("close", tmp_, err);
  }
  if (std::rename(tmp_.c_str(), dst_.c_str()) != 0) fail("rename " + tmp_ + " to", dst_, errno);
}

void write_file_atomic(const std::string& dir, const std::string& name, const std::string& text) {
  AtomicFileWriter w(dir, name);
  w.append(text);
  w.commit();
}

void write_file_atomic(const std::string& path, const std::string& text) {
  const std::filesystem::path p(path);
  write_file_atomic(p.has_parent_path() ? p.parent_path().string() : ".", p.filename().string(), text);
}

void prepare_output_dir(const std::string& dir, bool force, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::symlink_status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(fs::status(dir, ec)))
      throw ConfigError(option + " " + dir + ": exists and is not a folder");
    if (!force && !fs::exists(fs::path(dir) / kOutputMarker)) {
      for (const auto& e : fs::directory_iterator(dir))
        throw ConfigError(option + " " + dir + ": the folder is not empty (it holds " + e.path().filename().string() +
                          ") and is not an earlier output of this project (no " + kOutputMarker +
                          "): choose an empty or new folder, or add --force to write into it");
    }
  } else {
    fs::create_directories(dir, ec);
    if (ec) throw ConfigError(option + " " + dir + ": cannot create the folder: " + ec.message());
  }
  write_file_atomic(dir, kOutputMarker, "This folder holds outputs of rnav (radio-navigation estimators).\n");
}

std::string fixed(double x, int prec) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, x);
  return b;
}

std::string significant(double x, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

}  // namespace rnav
