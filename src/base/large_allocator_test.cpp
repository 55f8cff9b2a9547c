#include "base/large_allocator.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <algorithm>
#include <numeric>

namespace raycast {
namespace {

uintptr_t address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

TEST(LargeAllocator, LargeBlocksAreZeroedAlignedTo2MiBAndWritable) {
    // 3 MiB: the size of a 1024x1024 8-bit image. Not a multiple of the page size either.
    const size_t bytes = (size_t(3) << 20) + 5;
    void* block = allocate_large_block(bytes);
    ASSERT_NE(block, nullptr);
    EXPECT_EQ(address(block) % kLargeBlockBytes, 0u);
    const auto* zero = static_cast<const unsigned char*>(block);
    EXPECT_EQ(zero[0], 0);
    EXPECT_EQ(zero[bytes / 2], 0);
    EXPECT_EQ(zero[bytes - 1], 0);
    auto* data = static_cast<unsigned char*>(block);
    for (size_t i = 0; i < bytes; i += 4096) data[i] = static_cast<unsigned char>(i / 4096);
    data[bytes - 1] = 0xab;
    for (size_t i = 0; i < bytes; i += 4096) ASSERT_EQ(data[i], static_cast<unsigned char>(i / 4096)) << i;
    EXPECT_EQ(data[bytes - 1], 0xab);
    free_large_block(block, bytes);
}

TEST(LargeAllocator, VectorsOfEverySizeBehaveAsStdVector) {
    // Below, at and above the large-block threshold, growing across it and shrinking.
    for (size_t count : {size_t{0}, size_t{1}, size_t{1000}, kLargeBlockBytes / sizeof(uint32_t) - 1,
                         kLargeBlockBytes / sizeof(uint32_t), size_t(5) << 20}) {
        LargeVector<uint32_t> v(count);
        EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](uint32_t x) { return x == 0; })) << count;
        std::iota(v.begin(), v.end(), 7u);
        v.push_back(1);  // reallocates past the threshold for the larger counts
        ASSERT_EQ(v.size(), count + 1);
        for (size_t i = 0; i < count; i += 997) ASSERT_EQ(v[i], static_cast<uint32_t>(7 + i)) << count;
        EXPECT_EQ(v.back(), 1u);
        LargeVector<uint32_t> copy = v;
        EXPECT_TRUE(copy == v);
        v.resize(count / 2);
        v.resize(count);  // value-initialised again: zeros, not the old values
        for (size_t i = count / 2; i < count; i += 991) ASSERT_EQ(v[i], 0u) << count;
    }
}

TEST(LargeAllocator, SmallBlocksKeepTheAlignmentOfTheirType) {
    struct alignas(64) CacheLine {
        unsigned char bytes[64];
    };
    for (size_t count : {size_t{1}, size_t{3}, size_t{1000}}) {
        LargeVector<CacheLine> lines(count);
        EXPECT_EQ(address(lines.data()) % 64, 0u) << count;
    }
}

TEST(LargeAllocator, ImpossibleSizesThrowBadAlloc) {
    LargeAllocator<uint64_t> allocator;
    EXPECT_THROW(allocator.allocate(static_cast<size_t>(-1) / 4), std::bad_alloc);
    EXPECT_THROW(allocate_large_block(static_cast<size_t>(-1) - 100), std::bad_alloc);
}

}  // namespace
}  // namespace raycast
