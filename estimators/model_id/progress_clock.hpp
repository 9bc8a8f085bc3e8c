// The time a job of equal parts has spent and has left, for progress lines (no result depends on it).
#pragma once

#include <chrono>
#include <cstddef>
#include <stdexcept>

namespace rnav {

/// Started at construction; the time left is the mean time per part done so far times the parts
/// left: left = spent / done * (total - done).
class ProgressClock {
 public:
  /// @param total the job's parts, >= 1
  explicit ProgressClock(std::size_t total) : total_(total), start_(std::chrono::steady_clock::now()) {
    if (total < 1) throw std::invalid_argument("ProgressClock: a job of at least one part");
  }
  /// [s wall] since construction
  double spent_s() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  /// [s wall] the estimated time left with `done` parts done, done in [1, total]
  double left_s(std::size_t done) const {
    if (done < 1 || done > total_) throw std::invalid_argument("ProgressClock: parts done must be in [1, total]");
    return spent_s() / static_cast<double>(done) * static_cast<double>(total_ - done);
  }

 private:
  std::size_t total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace rnav
