// Process-wide memory settings for the programs that run the effect search.
#pragma once

namespace rnav::cli {

/// Keep freed memory in the process instead of handing it back to the kernel at once (glibc:
/// allocations up to 32 MiB from the heap, the heap trimmed only beyond 256 MiB free). Why: the
/// effect search allocates and frees temporaries of 100-300 kB (a whitened column of 15 000
/// observations) thousands of times a second; by default each went to mmap or was trimmed, and
/// the next one page-faulted its memory back. The nine Autoferry recordings pooled
/// (rnav_diagnose multi, 2 threads): 44.9 -> 39.9 s wall, 3.8 -> 1.0 s of system time, the
/// report identical. Results never depend on it. Call once, first thing in main().
void keep_freed_memory();

}  // namespace rnav::cli
