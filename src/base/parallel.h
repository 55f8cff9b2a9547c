// Work sharing over std::thread: items are claimed one at a time from an atomic counter, so
// the caller decides the grain (a tile, a chunk of a file). No global pool, no TBB.
#pragma once

#include <cstddef>
#include <functional>

namespace raycast {

/// The number of hardware threads, at least 1.
int hardware_threads();

/// Calls work(item, worker) for every item in [0, count) on up to `threads` threads (the caller's
/// thread among them); worker is in [0, threads). Returns when all items are done. If a call
/// throws, the remaining items are skipped and the first exception is rethrown here.
void parallel_for(size_t count, int threads, const std::function<void(size_t item, int worker)>& work);

}  // namespace raycast
