// Tests for triangle groups (geometry/triangle_groups.h): every triangle once, with the mesh's own
// corners, vertices shared. Their SIMD tests are in scene/mesh_kernel_test.cpp.
#include "geometry/triangle_groups.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // tests/trace_test_support.h

TEST(TriangleGroups, HoldEveryTriangleOnceWithItsCornersAndShareVertices) {
    std::mt19937 rng(51);
    const TriangleMesh grid = grid_mesh(rng, 6, 0.3f);
    std::vector<uint32_t> ids;
    for (uint32_t i = 0; i < grid.triangle_count(); ++i) ids.push_back(i);
    const std::vector<GroupBlock> groups = groups_of(grid, ids);
    std::vector<int> seen(ids.size(), 0);
    uint32_t group_count = 0, vertex_slots = 0;
    const GroupBlock* end = groups.data() + groups.size() - kGroupPaddingBlocks;
    for (const GroupBlock* group = groups.data(); group < end; group = next_group(group)) {
        ++group_count;
        vertex_slots += group_vertex_count(group);
        EXPECT_EQ(group_ends_leaf(group), next_group(group) == end);
        expect_group_of(group, grid, seen);
    }
    for (int s : seen) EXPECT_EQ(s, 1);
    // 72 triangles in groups of 8 (a strip of 8 grid triangles has 10 vertices): 9 groups, each
    // storing fewer vertices than its 24 corners.
    EXPECT_EQ(group_count, 9u);
    EXPECT_LT(vertex_slots, 12 * group_count);
}

}  // namespace
}  // namespace raycast
