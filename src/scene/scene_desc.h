// The scene exactly as the file describes it: a tree of groups and transforms over primitives,
// every node with its place in the file, before anything is flattened or built.
// Produced by sceneio (parse_scene.h), consumed by build_scene (build_scene.h).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/error.h"
#include "base/file_version.h"
#include "geometry/curve.h"
#include "geometry/plane.h"
#include "geometry/sphere.h"
#include "geometry/triangle_mesh.h"
#include "math/mat4.h"

namespace raycast {

struct CameraDesc {
    enum class Kind { Perspective, Orthographic };
    Kind kind = Kind::Perspective;
    Vec3f center, direction{0, 0, -1}, up{0, 1, 0};
    float angle_degrees = 0;  ///< perspective: the full field of view
    float size = 0;           ///< orthographic: the side of the view square in world units
    int width = 0, height = 0;  ///< 0 when the file gives no size (MIT 6.837 scenes)
    SourceLocation location;
};

struct LightDesc {
    enum class Kind { Directional, Point };
    Kind kind = Kind::Directional;
    Vec3f direction;  ///< directional: the way the light travels
    Vec3f position;   ///< point
    Vec3f color{1, 1, 1};
    Vec3f attenuation{1, 0, 0};  ///< point: constant, linear, quadratic (MIT 6.837 A4)
    SourceLocation location;
};

struct MaterialDesc {
    Vec3f diffuse{1, 1, 1};
    Vec3f specular{0, 0, 0};
    std::optional<float> shininess;  ///< `shininess` (course) or `exponent` (MIT); default by profile
    Vec3f reflective{0, 0, 0}, transparent{0, 0, 0};
    float index_of_refraction = 1;
    std::string texture;  ///< accepted and kept; not used by the ray caster
    SourceLocation location;
};

/// A loaded OBJ file; TriangleMesh objects refer to it by index, so a file used several times is
/// read once and stored once.
struct MeshDesc {
    MeshDesc() = default;
    MeshDesc(std::string path_, TriangleMesh mesh_, FileVersion version_ = {})
        : path(std::move(path_)), mesh(std::move(mesh_)), version(version_) {}

    std::string path;  ///< the path that opened it
    TriangleMesh mesh;
    /// The file as load_obj_file opened it (fstat on the file it read, not a second look by
    /// name, which could see a version saved while it was read).
    FileVersion version;
};

struct ObjectDesc {
    /// Curve: a BezierCurve or BsplineCurve, which is not a surface and draws nothing;
    /// RevSurface: `curve` (its profile) turned about the y axis.
    enum class Kind { Group, Sphere, Plane, Triangle, TriangleMesh, Transform, Curve, RevSurface };
    Kind kind = Kind::Group;
    SourceLocation location;
    int material = -1;  ///< primitives: the MaterialIndex in force where they appear
    Sphere sphere;
    Plane plane;
    Vec3f vertices[3];
    int mesh = -1;               ///< TriangleMesh: index into SceneDesc::meshes
    std::string mesh_path;       ///< TriangleMesh: the path as written
    SourceLocation mesh_path_location;
    Curve curve;                 ///< Curve: the curve; RevSurface: its profile
    Mat4 world_from_object;      ///< Transform: the composed matrix M (object → parent)
    std::vector<ObjectDesc> children;  ///< Group: its objects; Transform: exactly one
};

struct SceneDesc {
    std::string file;
    std::optional<CameraDesc> camera;
    Vec3f background{0.5f, 0.5f, 0.5f};
    std::optional<Vec3f> ambient;  ///< Background's ambientLight, if given
    bool has_lights_block = false;
    std::vector<LightDesc> lights;
    std::vector<MaterialDesc> materials;
    std::optional<ObjectDesc> root;  ///< the top-level Group
    std::vector<MeshDesc> meshes;
    std::vector<Diagnostic> warnings;
    /// The scene file's text, from which build_scene shows the lines of the errors it finds.
    std::string source_text;
};

}  // namespace raycast
