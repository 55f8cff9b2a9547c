// Where the parts of a triangle group lie (geometry/triangle_groups.h describes the format). No
// include guard and no includes: every user includes it inside its own namespace, so that the
// SIMD kernels, each compiled for its own instruction set, get their own copies of these inline
// functions (see scene/packet_view.h for why they must not share one).

// Byte offsets from the start of a group of `triangles` triangles and `vertices` vertices.
inline uint32_t group_corners_offset() { return 4; }
inline uint32_t group_vertices_offset(uint32_t triangles) { return (4 + 3 * triangles + 3) & ~3u; }
inline uint32_t group_ids_offset(uint32_t triangles, uint32_t vertices) {
    return group_vertices_offset(triangles) + 12 * vertices;
}
// The group's size in 16-byte blocks.
inline uint32_t group_blocks(uint32_t triangles, uint32_t vertices) {
    return (group_ids_offset(triangles, vertices) + 4 * triangles + 15) / 16;
}
