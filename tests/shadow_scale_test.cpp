// Shadows at every scene scale: the same scene built at scales from 1e-3 to 1e4 (every length
// multiplied by s) must give the same --shadows image. A fixed epsilon for the shadow ray's origin
// breaks at one end or the other (self-shadowing acne when it is too small for the coordinates,
// light leaking under contact points when it is too large); raycast offsets the origin by the hit
// point's own rounding-error bound, so the image does not depend on s.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "base/error.h"
#include "image/compare_images.h"
#include "image/image_io.h"
#include "test_support.h"

namespace raycast {
namespace {

// A sphere resting on a plane, a second sphere floating above a triangle, and a small mesh-free
// cube of triangles, lit by a point light whose shadows fall across the floor: every primitive
// both casts and receives shadows. All lengths are multiplied by `s`.
std::string scene_at_scale(double s) {
    auto v = [s](double x, double y, double z) { return string_printf("%.9g %.9g %.9g", x * s, y * s, z * s); };
    return "PerspectiveCamera { center " + v(0, 3, 10) + " direction 0 -0.3 -1 up 0 1 0 angle 35 width 120 height 90 }\n"
           "Lights { numLights 2\n"
           "  PointLight { position " + v(-4, 8, 5) + " color 0.8 0.8 0.8 }\n"
           "  DirectionalLight { direction 0.3 -1 -0.2 color 0.3 0.3 0.3 } }\n"
           "Background { color 0.1 0.1 0.2 }\n"
           "Materials { numMaterials 2\n"
           "  PhongMaterial { diffuseColor 0.8 0.8 0.8 }\n"
           "  PhongMaterial { diffuseColor 0.9 0.3 0.2 specularColor 0.5 0.5 0.5 shininess 20 } }\n"
           "Group { numObjects 5\n"
           "  MaterialIndex 0\n"
           "  Plane { normal 0 1 0 offset " + string_printf("%.9g", -1 * s) + " }\n"
           "  Triangle { vertex0 " + v(1, -0.5, 0) + " vertex1 " + v(3.5, -0.5, 0) + " vertex2 " + v(2.2, -0.5, -2.5) + " }\n"
           "  MaterialIndex 1\n"
           "  Sphere { center " + v(-1.5, 0, 0) + " radius " + string_printf("%.9g", 1 * s) + " }\n"
           "  Sphere { center " + v(2.2, 0.8, -0.8) + " radius " + string_printf("%.9g", 0.6 * s) + " }\n"
           "  Transform { Translate " + v(0.2, -0.5, 1.5) + " UniformScale " + string_printf("%.9g", s) +
           " YRotate 30 Scale 0.5 0.5 0.5 Sphere { center 0 0 0 radius 1 } }\n"
           "}\n";
}

ImageRgb8 render_at_scale(double s, const std::string& name) {
    const std::string dir = test::temp_dir("shadow-scale-" + name);
    test::write_file(dir + "/scene.txt", scene_at_scale(s));
    const test::RunResult run = test::run_raycast("--quiet --shadows scene.txt out.ppm", dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_image(dir + "/out.ppm");
}

TEST(ShadowScale, ImageIsTheSameFromScaleOneThousandthToTenThousand) {
    const ImageRgb8 unit = render_at_scale(1, "1");
    // The scene does have shadows: with --shadows it is darker somewhere than without.
    const std::string dir = test::temp_dir("shadow-scale-unlit");
    test::write_file(dir + "/scene.txt", scene_at_scale(1));
    ASSERT_EQ(test::run_raycast("--quiet scene.txt out.ppm", dir).exit_code, 0);
    const ImageComparison with_without = compare_images(unit, read_image(dir + "/out.ppm"));
    ASSERT_GT(with_without.differing_pixels, with_without.pixel_count / 50) << "the test scene casts no shadows";

    for (const double s : {1e-3, 1e-2, 1e2, 1e4}) {
        const ImageRgb8 scaled = render_at_scale(s, string_printf("%g", s));
        const ImageComparison c = compare_images(unit, scaled);
        // Rounding of the scaled coordinates moves a few silhouette pixels; acne or leaks would
        // change hundreds.
        EXPECT_LE(c.pixels_beyond(1), c.pixel_count / 1000)
            << "scale " << s << ": " << c.pixels_beyond(1) << " pixels differ by more than one level";
    }
}

}  // namespace
}  // namespace raycast
