#include "sceneio/write_obj.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "base/error.h"

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
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) throw InputError(path, std::string("cannot write OBJ file: ") + std::strerror(errno));
    const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
    const bool closed = std::fclose(file) == 0;
    if (!written || !closed) throw InputError(path, "cannot write OBJ file: the disk may be full");
}

}  // namespace raycast
