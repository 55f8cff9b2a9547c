// Building blocks for scenes made in code by the unit tests: one-line constructors for the scene
// description's objects, materials and lights, a cube mesh, and build() with given conventions.
#pragma once

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

inline Scene build(SceneDesc desc, Conventions conventions = Conventions::course()) {
    SceneBuildOptions options;
    options.conventions = conventions;
    return build_scene(std::move(desc), options);
}

}  // namespace raycast::test
