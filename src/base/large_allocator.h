// An allocator for big arrays (images, and anything else that runs to megabytes): blocks of
// 2 MiB and more come straight from the operating system, aligned to 2 MiB and marked for
// transparent huge pages, so that the kernel can back them with 2 MiB pages.
//
// Why: touching fresh memory costs one page fault per 4 KiB page. On a bare machine that is a
// fraction of a microsecond, but on a virtual machine a fault can cost 10-15 µs (measured on
// the benchmark machine: a 1024x1024 8-bit image, 3 MiB, took 11 ms to zero with 4 KiB pages,
// a tenth of a render). With huge pages the same image takes two faults. Embree allocates its
// BVHs the same way. Where huge pages are unavailable this is an ordinary allocation.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace raycast {

/// Blocks at least this large are mapped with huge-page advice; smaller ones use operator new.
constexpr size_t kLargeBlockBytes = size_t(2) << 20;

/// `bytes` of zeroed, 2 MiB-aligned memory with huge-page advice (bytes >= kLargeBlockBytes).
/// Throws std::bad_alloc when the system has no memory for it.
void* allocate_large_block(size_t bytes);
/// Returns a block from allocate_large_block; `bytes` is the size it was allocated with.
void free_large_block(void* block, size_t bytes);

/// Asks for transparent huge pages on the whole 4 KiB pages of [data, data + bytes), if bytes is
/// at least 2 MiB, before they are first written (for arrays allocated elsewhere, such as a
/// std::vector after reserve()). Only advice: where the kernel has no THP, nothing changes.
void advise_huge_pages(const void* data, size_t bytes);

template <typename T>
struct LargeAllocator {
    using value_type = T;

    LargeAllocator() = default;
    template <typename U>
    LargeAllocator(const LargeAllocator<U>&) noexcept {}

    // Small blocks honour alignof(T) as std::allocator does (a BVH node may ask for a cache
    // line); large ones are aligned to 2 MiB anyway.
    T* allocate(size_t n) {
        if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_alloc();
        const size_t bytes = n * sizeof(T);
        if (bytes < kLargeBlockBytes) return static_cast<T*>(::operator new(bytes, std::align_val_t{alignof(T)}));
        return static_cast<T*>(allocate_large_block(bytes));
    }
    void deallocate(T* p, size_t n) noexcept {
        const size_t bytes = n * sizeof(T);
        if (bytes < kLargeBlockBytes) {
            ::operator delete(p, std::align_val_t{alignof(T)});
            return;
        }
        free_large_block(p, bytes);
    }
};

template <typename T, typename U>
bool operator==(const LargeAllocator<T>&, const LargeAllocator<U>&) noexcept { return true; }
template <typename T, typename U>
bool operator!=(const LargeAllocator<T>&, const LargeAllocator<U>&) noexcept { return false; }

/// A std::vector whose big buffers come from LargeAllocator.
template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace raycast
