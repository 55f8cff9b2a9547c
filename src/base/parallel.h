// Work sharing over std::thread: items are claimed one at a time from an atomic counter, so
// the caller decides the grain (a tile, a chunk of a file). The threads that help the caller are
// kept from one call to the next (parallel.cpp says why); no TBB.
#pragma once

#include <cstddef>
#include <functional>

namespace raycast {

/// The number of hardware threads, at least 1.
int hardware_threads();

/// How long a helper thread that worked on a call stays awake for the next one, yielding its
/// processor between looks, before it sleeps (parallel.cpp says why).
constexpr int kHelperStayAwakeMilliseconds = 20;

/// Calls work(item, worker) for every item in [0, count) on up to `threads` threads (the caller's
/// thread among them); worker is in [0, threads). Returns when all items are done. If a call
/// throws, the remaining items are skipped and the first exception is rethrown here. Calls made
/// at once from several threads, or from inside `work`, are safe: one at a time uses the kept
/// helper threads, the others threads of their own.
void parallel_for(size_t count, int threads, const std::function<void(size_t item, int worker)>& work);

/// Runs `work` on a new thread with a stack of `stack_bytes` and waits for it; an exception it
/// throws is rethrown here. For code that recurses once per level of the input (the scene parser
/// follows nested groups): a sanitizer build needs about 10 KiB of stack per level, so the
/// nesting limit would not fit in a default 8 MiB stack. The memory is reserved, and only the
/// pages actually used are committed.
void call_with_stack(size_t stack_bytes, const std::function<void()>& work);

/// Stack for the recursive passes over a scene: 128 MiB, a dozen times what the nesting limit
/// needs in a sanitizer build.
constexpr size_t kDeepRecursionStackBytes = size_t{128} << 20;

/// The most levels of recursion run on the calling thread's own stack: 64 levels of a sanitizer
/// build's 10 KiB are 640 KiB, well within any thread's default stack.
constexpr size_t kShallowRecursionLevels = 64;

/// Runs `work`, which recurses at most `levels` deep (an upper bound), here when that is at most
/// kShallowRecursionLevels, and otherwise with call_with_stack(kDeepRecursionStackBytes). Starting
/// that thread (its 128 MiB stack, its first malloc making an arena) took about 115 µs: half of
/// loading a small scene, for nesting that a small scene does not have.
void call_with_stack_for_depth(size_t levels, const std::function<void()>& work);

}  // namespace raycast
