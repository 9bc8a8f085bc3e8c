#include "common/io/process_memory.hpp"

#include <malloc.h>

namespace rnav::cli {

void keep_freed_memory() {
  // 32 MiB is glibc's largest mmap threshold on 64-bit (a larger value is refused); setting
  // either value also stops glibc's own adjustment of both.
  constexpr int kMmapThresholdBytes = 32 << 20, kTrimThresholdBytes = 256 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
}

}  // namespace rnav::cli
