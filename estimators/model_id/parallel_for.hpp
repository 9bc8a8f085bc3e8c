// fn(0) ... fn(n - 1) on up to `threads` threads (this one among them), each index once. When
// calls throw, the exception of the lowest index is rethrown after all have finished (the same
// error whatever the scheduling). Used by the searches' candidates, injections, tracks and
// recordings left out.
//
// The helper threads are kept for the process's life (a pool grown to the most ever needed at
// once, parallel_for.cpp) so that what a thread keeps between calls (the gain tables and Gram
// entries of noise identification) serves the next call too: with a thread started per call,
// every injected search's helper began with nothing kept. Nested calls cannot wait for each
// other: a call that finds no idle helper starts one.
#pragma once

#include <cstddef>
#include <functional>

namespace rnav {

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn);

}  // namespace rnav
