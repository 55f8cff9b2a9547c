// raycast_meshgen: seeded OBJ meshes for demos, tests and benchmarks.
//   raycast_meshgen SHAPE TRIANGLES OUTPUT.obj [--seed N] [--quads] [--normals] [--bumps A]
// SHAPE is bumpy-sphere (a closed, watertight mesh: every edge shared by two triangles),
// terrain (a height field over [-1, 1]²) or torus. The count is a target: the mesh gets the
// nearest count its grid allows, and the tool prints the exact one.
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "base/command_line.h"
#include "base/error.h"
#include "base/write_file.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// SplitMix64: a tiny seeded generator, so the same seed always gives the same mesh.
struct Random {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
};

// A sum of random waves over the unit sphere (or plane): smooth bumps with a seeded layout.
struct Bumps {
    struct Wave {
        double dx, dy, dz, frequency, phase, amplitude;
    };
    std::vector<Wave> waves;
    Bumps(uint64_t seed, double amplitude) {
        Random random{seed};
        for (int i = 0; i < 12; ++i) {
            double x = random.uniform() * 2 - 1, y = random.uniform() * 2 - 1, z = random.uniform() * 2 - 1;
            const double len = std::sqrt(x * x + y * y + z * z) + 1e-9;
            const double frequency = 2 + 10 * random.uniform();
            waves.push_back({x / len, y / len, z / len, frequency, random.uniform() * 2 * kPi,
                             amplitude / (1 + 0.35 * frequency)});
        }
    }
    double at(double x, double y, double z) const {
        double sum = 0;
        for (const Wave& w : waves) sum += w.amplitude * std::sin(w.frequency * (w.dx * x + w.dy * y + w.dz * z) + w.phase);
        return sum;
    }
};

struct Mesh {
    std::vector<double> positions;  // xyz
    std::vector<double> normals;    // xyz, optional
    std::vector<std::vector<uint32_t>> faces;
};

void add_vertex(Mesh& mesh, double x, double y, double z) {
    mesh.positions.insert(mesh.positions.end(), {x, y, z});
}

// Latitude-longitude sphere: `rings` latitude bands, `segments` around; caps are fans to the poles.
Mesh bumpy_sphere(int rings, int segments, const Bumps& bumps, bool quads) {
    Mesh mesh;
    auto radius = [&](double x, double y, double z) { return 1 + bumps.at(x, y, z); };
    add_vertex(mesh, 0, radius(0, 1, 0), 0);  // north pole: 0
    for (int r = 1; r < rings; ++r) {
        const double theta = kPi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2 * kPi * s / segments;
            const double x = std::sin(theta) * std::cos(phi), y = std::cos(theta), z = std::sin(theta) * std::sin(phi);
            const double k = radius(x, y, z);
            add_vertex(mesh, k * x, k * y, k * z);
        }
    }
    const uint32_t south = static_cast<uint32_t>(mesh.positions.size() / 3);
    add_vertex(mesh, 0, -radius(0, -1, 0), 0);
    auto at = [&](int r, int s) { return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments)); };
    for (int s = 0; s < segments; ++s) mesh.faces.push_back({0, at(1, s + 1), at(1, s)});
    for (int r = 1; r + 1 < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = at(r, s), b = at(r, s + 1), c = at(r + 1, s + 1), d = at(r + 1, s);
            if (quads) {
                mesh.faces.push_back({a, b, c, d});
            } else {
                mesh.faces.push_back({a, b, c});
                mesh.faces.push_back({a, c, d});
            }
        }
    for (int s = 0; s < segments; ++s) mesh.faces.push_back({south, at(rings - 1, s), at(rings - 1, s + 1)});
    return mesh;
}

Mesh terrain(int n, const Bumps& bumps, bool quads) {
    Mesh mesh;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = 2.0 * i / (n - 1) - 1, z = 2.0 * j / (n - 1) - 1;
            add_vertex(mesh, x, bumps.at(x, 0, z), z);
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const uint32_t a = static_cast<uint32_t>(j * n + i), b = a + 1, c = a + static_cast<uint32_t>(n) + 1,
                           d = a + static_cast<uint32_t>(n);
            if (quads) {
                mesh.faces.push_back({a, d, c, b});
            } else {
                mesh.faces.push_back({a, d, c});
                mesh.faces.push_back({a, c, b});
            }
        }
    return mesh;
}

Mesh torus(int rings, int segments, bool quads, bool with_normals) {
    Mesh mesh;
    const double major = 1.0, minor = 0.35;
    for (int r = 0; r < rings; ++r) {
        const double u = 2 * kPi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double v = 2 * kPi * s / segments;
            const double nx = std::cos(v) * std::cos(u), ny = std::sin(v), nz = std::cos(v) * std::sin(u);
            add_vertex(mesh, (major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
                       (major + minor * std::cos(v)) * std::sin(u));
            if (with_normals) mesh.normals.insert(mesh.normals.end(), {nx, ny, nz});
        }
    }
    auto at = [&](int r, int s) { return static_cast<uint32_t>((r % rings) * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = at(r, s), b = at(r, s + 1), c = at(r + 1, s + 1), d = at(r + 1, s);
            if (quads) {
                mesh.faces.push_back({a, b, c, d});
            } else {
                mesh.faces.push_back({a, b, c});
                mesh.faces.push_back({a, c, d});
            }
        }
    return mesh;
}

size_t triangle_count(const Mesh& mesh) {
    size_t count = 0;
    for (const auto& face : mesh.faces) count += face.size() - 2;
    return count;
}

// Writes the OBJ text to `fd`, formatted as it goes (a mesh of millions of triangles is never
// held as text); returns 0 or the errno of a failed write.
int write_obj_text(int fd, const Mesh& mesh, const std::string& header) {
    const int own = ::dup(fd);  // fclose closes it; the writer closes fd
    std::FILE* file = own < 0 ? nullptr : ::fdopen(own, "wb");
    if (!file) {
        const int error = errno;
        if (own >= 0) ::close(own);
        return error;
    }
    std::fprintf(file, "# %s\n", header.c_str());
    std::vector<char> buffer(1 << 20);
    std::setvbuf(file, buffer.data(), _IOFBF, buffer.size());
    for (size_t i = 0; i < mesh.positions.size(); i += 3)
        std::fprintf(file, "v %.6f %.6f %.6f\n", mesh.positions[i], mesh.positions[i + 1], mesh.positions[i + 2]);
    for (size_t i = 0; i < mesh.normals.size(); i += 3)
        std::fprintf(file, "vn %.6f %.6f %.6f\n", mesh.normals[i], mesh.normals[i + 1], mesh.normals[i + 2]);
    const bool normals = !mesh.normals.empty();
    for (const auto& face : mesh.faces) {
        std::fputc('f', file);
        for (uint32_t index : face) {
            if (normals)
                std::fprintf(file, " %u//%u", index + 1, index + 1);
            else
                std::fprintf(file, " %u", index + 1);
        }
        std::fputc('\n', file);
    }
    int error = std::ferror(file) ? (errno != 0 ? errno : EIO) : 0;
    if (std::fclose(file) != 0 && error == 0) error = errno;
    return error;
}

// A number as a whole argument: "1e3junk", "0x100", "nan" and "inf" are refused (atof had read
// them as 1000, 0, and a mesh of NaN vertices).
bool read_number(const char* text, double& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtod(text, &end);
    return *text != '\0' && *end == '\0' && errno == 0 && std::isfinite(value) &&
           std::strpbrk(text, "xXnN") == nullptr;  // no hexadecimal, no nan or inf
}

constexpr const char* kUsage =
    "usage: raycast_meshgen bumpy-sphere|terrain|torus TRIANGLES OUTPUT.obj [--seed N] [--quads] [--normals]\n"
    "                       [--bumps AMPLITUDE]\n"
    "Writes a test mesh of about TRIANGLES triangles (8 to 200000000; it prints the exact count): a\n"
    "closed sphere of radius about 1 with smooth random bumps, a height field over [-1, 1]^2, or a torus.\n"
    "--seed picks the bumps (default 1), --bumps their height as a fraction of the radius (0 to 1,\n"
    "default 0.04; not for a torus), --quads writes quads, --normals vertex normals (torus only).\n";

int usage() {
    std::fputs(kUsage, stderr);
    return 2;
}

int generate(int argc, char** argv) {
    const std::vector<std::string> args = raycast::split_attached_values(argc, argv);  // "--seed=3" as "--seed 3"
    if (raycast::asks_for_help(args)) {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (args.size() < 3) return usage();
    const std::string shape = args[0];
    double target = 0;
    if (!read_number(args[1].c_str(), target) || !(target >= 8) || target > 2e8) {
        std::fprintf(stderr, "raycast_meshgen: TRIANGLES must be a number from 8 to 200000000, got '%s'\n",
                     args[1].c_str());
        return 2;
    }
    const std::string output = args[2];
    uint64_t seed = 1;
    bool quads = false, with_normals = false, bumps_given = false;
    double amplitude = 0.04;
    for (size_t i = 3; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--seed" && i + 1 < args.size()) {
            const char* text = args[++i].c_str();
            char* end = nullptr;
            errno = 0;
            seed = std::strtoull(text, &end, 10);
            if (*text < '0' || *text > '9' || *end != '\0' || errno != 0) {
                std::fprintf(stderr, "raycast_meshgen: --seed needs a whole number from 0 to 2^64 - 1, got '%s'\n", text);
                return 2;
            }
        } else if (arg == "--quads") {
            quads = true;
        } else if (arg == "--normals") {
            with_normals = true;
        } else if (arg == "--bumps" && i + 1 < args.size()) {
            // Bumps are a fraction of the unit radius: past 1 the surface folds through itself.
            if (!read_number(args[++i].c_str(), amplitude) || amplitude < 0 || amplitude > 1) {
                std::fprintf(stderr, "raycast_meshgen: --bumps needs a number from 0 to 1, got '%s'\n",
                             args[i].c_str());
                return 2;
            }
            bumps_given = true;
        } else {
            return usage();
        }
    }
    if (bumps_given && shape == "torus") {
        std::fputs("raycast_meshgen: --bumps is for bumpy-sphere and terrain; a torus has none\n", stderr);
        return 2;
    }
    const Bumps bumps(seed, amplitude);
    Mesh mesh;
    if (shape == "bumpy-sphere") {
        // 2·segments·(rings − 1) triangles, with segments close to 2·rings.
        const int rings = std::max(2, static_cast<int>(std::lround(std::sqrt(target / 4))) + 1);
        const int segments = std::max(3, static_cast<int>(std::lround(target / (2.0 * (rings - 1)))));
        mesh = bumpy_sphere(rings, segments, bumps, quads);
    } else if (shape == "terrain") {
        const int n = std::max(2, static_cast<int>(std::lround(std::sqrt(target / 2)) + 1));
        mesh = terrain(n, bumps, quads);
    } else if (shape == "torus") {
        const int segments = std::max(3, static_cast<int>(std::lround(std::sqrt(target / 4))));
        const int rings = std::max(3, static_cast<int>(std::lround(target / (2.0 * segments))));
        mesh = torus(rings, segments, quads, with_normals);
    } else {
        return usage();
    }
    if (with_normals && mesh.normals.empty()) {
        std::fputs("raycast_meshgen: --normals is available for torus only\n", stderr);
        return 2;
    }
    const size_t triangles = triangle_count(mesh);
    const std::string header = "raycast_meshgen " + shape + " " + std::to_string(triangles) + " triangles, seed " +
                               std::to_string(seed);
    // As raycast writes its images (base/write_file.h): a temporary file renamed into place, so a
    // failed write (a full disk) leaves no mesh cut mid-line, which, cut at a line's end, would
    // load as a smaller mesh with no error; links written through, pipes and devices into.
    try {
        raycast::write_file_atomically(output, [&](int fd) { return write_obj_text(fd, mesh, header); }, "OBJ file");
    } catch (const raycast::InputError& error) {
        std::fputs(error.what(), stderr);  // "OUTPUT: error: cannot write OBJ file: <reason>", as raycast says it
        return 1;
    }
    std::printf("%s: %zu vertices, %zu triangles\n", output.c_str(), mesh.positions.size() / 3, triangles);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return generate(argc, argv);
    } catch (const std::bad_alloc&) {
        // About 80 bytes a triangle while the mesh is made: 2e8 triangles need some 16 GB.
        std::fputs("raycast_meshgen: error: out of memory: ask for fewer triangles\n", stderr);
        return 1;
    }
}
