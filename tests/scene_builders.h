// Building blocks for scenes made in code by the unit tests: one-line constructors for the scene
// description's objects, materials and lights, a cube and a UV sphere mesh (and either turned
// inside out), and build() with given conventions.
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include "scene/build_scene.h"
#include "scene/scene_desc.h"

namespace raycast::test {

/// A perspective camera of `angle` degrees, width × height pixels.
inline CameraDesc perspective(Vec3f center, Vec3f direction, Vec3f up, float angle, int width, int height) {
    CameraDesc desc;
    desc.kind = CameraDesc::Kind::Perspective;
    desc.center = center;
    desc.direction = direction;
    desc.up = up;
    desc.angle_degrees = angle;
    desc.width = width;
    desc.height = height;
    return desc;
}

inline ObjectDesc sphere(Vec3f center, float radius, int material = 0) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Sphere;
    o.sphere = {center, radius};
    o.material = material;
    return o;
}

inline ObjectDesc plane(Vec3f normal, float offset, int material = 0) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Plane;
    o.plane = {normal, offset};
    o.material = material;
    return o;
}

inline ObjectDesc triangle(Vec3f a, Vec3f b, Vec3f c, int material = 0) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Triangle;
    o.vertices[0] = a;
    o.vertices[1] = b;
    o.vertices[2] = c;
    o.material = material;
    return o;
}

/// An instance of desc.meshes[mesh].
inline ObjectDesc mesh_object(int mesh, int material = 0) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::TriangleMesh;
    o.mesh = mesh;
    o.material = material;
    return o;
}

/// A BezierCurve or BsplineCurve on its own (it draws nothing).
inline ObjectDesc curve_object(Curve curve) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Curve;
    o.curve = std::move(curve);
    return o;
}

/// A RevSurface turning `profile` about the y axis.
inline ObjectDesc rev_surface(Curve profile, int material = 0) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::RevSurface;
    o.curve = std::move(profile);
    o.material = material;
    return o;
}

inline ObjectDesc transform(const Mat4& m, ObjectDesc child, SourceLocation location = {}) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Transform;
    o.world_from_object = m;
    o.location = std::move(location);
    o.children.push_back(std::move(child));
    return o;
}

inline ObjectDesc group(std::vector<ObjectDesc> children) {
    ObjectDesc o;
    o.kind = ObjectDesc::Kind::Group;
    o.children = std::move(children);
    return o;
}

inline MaterialDesc material(Vec3f kd, Vec3f ks = {0, 0, 0}, float shininess = 0) {
    MaterialDesc m;
    m.diffuse = kd;
    m.specular = ks;
    m.shininess = shininess;
    return m;
}

inline LightDesc directional(Vec3f direction, Vec3f color) {
    LightDesc l;
    l.kind = LightDesc::Kind::Directional;
    l.direction = direction;
    l.color = color;
    return l;
}

inline LightDesc point_light(Vec3f position, Vec3f color) {
    LightDesc l;
    l.kind = LightDesc::Kind::Point;
    l.position = position;
    l.color = color;
    return l;
}

/// The cube [−1, 1]³ with counter-clockwise outward faces, like the course's cube.obj.
inline TriangleMesh cube_mesh() {
    TriangleMesh mesh;
    mesh.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    mesh.indices = {4, 5, 6, 4, 6, 7, 0, 2, 1, 0, 3, 2, 1, 2, 6, 1, 6, 5,
                    0, 4, 7, 0, 7, 3, 3, 7, 6, 3, 6, 2, 0, 1, 5, 0, 5, 4};
    return mesh;
}

// A closed UV sphere: poles and rings share their vertices, the seam wraps around by index.
inline TriangleMesh sphere_mesh(Vec3f centre, float radius, int rings, int segments) {
    TriangleMesh mesh;
    mesh.positions.push_back(centre + Vec3f{0, radius, 0});
    for (int r = 1; r < rings; ++r) {
        const float theta = 3.14159265f * static_cast<float>(r) / static_cast<float>(rings);
        for (int s = 0; s < segments; ++s) {
            const float phi = 6.2831853f * static_cast<float>(s) / static_cast<float>(segments);
            mesh.positions.push_back(centre + Vec3f{std::sin(theta) * std::cos(phi), std::cos(theta),
                                                    std::sin(theta) * std::sin(phi)} *
                                                  radius);
        }
    }
    const uint32_t south = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.push_back(centre - Vec3f{0, radius, 0});
    auto ring_vertex = [&](int r, int s) {
        return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments));
    };
    auto add = [&](uint32_t a, uint32_t b, uint32_t c) { mesh.indices.insert(mesh.indices.end(), {a, b, c}); };
    for (int s = 0; s < segments; ++s) {
        add(0, ring_vertex(1, s + 1), ring_vertex(1, s));
        for (int r = 1; r + 1 < rings; ++r) {
            add(ring_vertex(r, s), ring_vertex(r, s + 1), ring_vertex(r + 1, s + 1));
            add(ring_vertex(r, s), ring_vertex(r + 1, s + 1), ring_vertex(r + 1, s));
        }
        add(south, ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1));
    }
    return mesh;
}

// The mesh with every triangle wound the other way (its corners' normals kept with them): still
// closed if it was, every face turned the other way.
inline TriangleMesh inside_out(TriangleMesh mesh) {
    for (size_t i = 0; i < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
    for (size_t i = 0; i + 2 < mesh.normal_indices.size(); i += 3)
        std::swap(mesh.normal_indices[i + 1], mesh.normal_indices[i + 2]);
    return mesh;
}

inline Scene build(SceneDesc desc, Conventions conventions = Conventions::course()) {
    SceneBuildOptions options;
    options.conventions = conventions;
    return build_scene(std::move(desc), options);
}

}  // namespace raycast::test
