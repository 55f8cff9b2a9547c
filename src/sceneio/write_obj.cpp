#include "sceneio/write_obj.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "base/error.h"
#include "base/write_file.h"

namespace raycast {

std::string obj_text(const TriangleMesh& mesh) {
    std::string text;
    char line[128];
    for (const Vec3f& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        text += line;
    }
    for (const Vec3f& n : mesh.normals) {
        std::snprintf(line, sizeof line, "vn %.9g %.9g %.9g\n", double(n.x), double(n.y), double(n.z));
        text += line;
    }
    for (size_t i = 0; i < mesh.triangle_count(); ++i) {
        text += 'f';
        for (size_t k = 0; k < 3; ++k) {
            const unsigned vertex = mesh.indices[3 * i + k] + 1;
            const bool has_normal = mesh.has_normals() && mesh.normal_indices[3 * i + k] != kNoNormal;
            if (has_normal)
                std::snprintf(line, sizeof line, " %u//%u", vertex, mesh.normal_indices[3 * i + k] + 1);
            else
                std::snprintf(line, sizeof line, " %u", vertex);
            text += line;
        }
        text += '\n';
    }
    return text;
}

void write_obj_file(const std::string& path, const TriangleMesh& mesh) {
    const std::string text = obj_text(mesh);
    // Atomically: a failed write (a full disk) left a mesh cut mid-line, and one cut at a line's
    // end would load as a smaller mesh with no error.
    write_file_atomically(path, std::string_view(text), "OBJ file");
}

}  // namespace raycast
