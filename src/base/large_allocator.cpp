#include "base/large_allocator.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace raycast {

namespace {

constexpr size_t kPageBytes = 4096;

size_t round_up(size_t value, size_t multiple) { return (value + multiple - 1) / multiple * multiple; }

}  // namespace

#if defined(__linux__)

void* allocate_large_block(size_t bytes) {
    const size_t length = round_up(bytes, kPageBytes);
    if (length < bytes || length > SIZE_MAX - kLargeBlockBytes) throw std::bad_alloc();
    // Map 2 MiB more than needed, then unmap the ends so that what is left starts on a 2 MiB
    // boundary: only whole aligned 2 MiB ranges can become huge pages.
    void* mapping = mmap(nullptr, length + kLargeBlockBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapping == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t start = reinterpret_cast<uintptr_t>(mapping);
    const uintptr_t aligned = round_up(start, kLargeBlockBytes);
    if (aligned > start) munmap(mapping, aligned - start);
    const uintptr_t end = start + length + kLargeBlockBytes;
    if (end > aligned + length) munmap(reinterpret_cast<void*>(aligned + length), end - (aligned + length));
    advise_huge_pages(reinterpret_cast<void*>(aligned), length);
    return reinterpret_cast<void*>(aligned);
}

void free_large_block(void* block, size_t bytes) {
    if (block) munmap(block, round_up(bytes, kPageBytes));
}

#else

void* allocate_large_block(size_t bytes) { return ::operator new(bytes); }
void free_large_block(void* block, size_t) { ::operator delete(block); }

#endif

void advise_huge_pages(const void* data, size_t bytes) {
#ifdef MADV_HUGEPAGE
    const uintptr_t first = round_up(reinterpret_cast<uintptr_t>(data), kPageBytes);
    const uintptr_t last = (reinterpret_cast<uintptr_t>(data) + bytes) / kPageBytes * kPageBytes;
    if (bytes >= kLargeBlockBytes && last > first)
        madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

}  // namespace raycast
