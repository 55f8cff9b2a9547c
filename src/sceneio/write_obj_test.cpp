// write_obj (sceneio/write_obj.h): what it writes, load_obj reads back exactly: the same positions,
// normals and faces, to the last bit of every float.
#include "sceneio/write_obj.h"

#include <gtest/gtest.h>

#include "sceneio/load_obj.h"

namespace raycast {
namespace {

TEST(WriteObjTest, WritesVerticesNormalsAndFacesAsOneBasedIndices) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    EXPECT_EQ(obj_text(mesh), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    mesh.normals = {{0, 0, 1}};
    mesh.normal_indices = {0, 0, 0};
    EXPECT_EQ(obj_text(mesh), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
}

TEST(WriteObjTest, LoadObjReadsBackTheSameMeshExactly) {
    TriangleMesh mesh;
    for (int i = 0; i < 50; ++i) {
        const float a = 0.1234567f * static_cast<float>(i);
        mesh.positions.push_back({a, 1 / (a + 3), -a * a * 1e-3f});
        mesh.normals.push_back(normalize(Vec3f{1, a, 0.5f}));
    }
    for (uint32_t i = 0; i + 2 < 50; ++i) {
        mesh.indices.insert(mesh.indices.end(), {i, i + 1, i + 2});
        mesh.normal_indices.insert(mesh.normal_indices.end(), {i + 2, i, i + 1});
    }
    const TriangleMesh read = parse_obj(obj_text(mesh), "round_trip.obj");
    EXPECT_EQ(read.positions.size(), mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_EQ(read.positions[i], mesh.positions[i]) << i;
        EXPECT_EQ(read.normals[i], mesh.normals[i]) << i;
    }
    EXPECT_EQ(read.indices, mesh.indices);
    EXPECT_EQ(read.normal_indices, mesh.normal_indices);
}

}  // namespace
}  // namespace raycast
