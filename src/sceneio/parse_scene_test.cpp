// parse_scene() on scene text in memory: every block of the course's PA1 grammar with its
// defaults (docs: ../shared/docs/course-format.md §a), fields in any order, Group counting and the
// course's file-wide MaterialIndex, every Transform item with the course's composition order (checked
// by mapping points through the composed matrix, values worked out by hand in the comments), the
// MIT 6.837 F04 forms (OrthographicCamera, ambientLight, exponent, attenuation, row-major Matrix, ...),
// and finally every scene on disk (the course's 7 and MIT's a1-a4) through load_scene_file.
// Malformed input and the exact diagnostics are covered by tests/parse_errors/ (golden files).
#include "sceneio/parse_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "base/limits.h"
#include "sceneio/load_scene.h"
#include "test_support.h"

namespace raycast {
namespace {

const std::string kCamera =
    "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 20 height 10 }\n";
const std::string kOneMaterial = "Materials { numMaterials 1 Material { } }\n";
const std::string kUnitSphere = "Sphere { center 0 0 0 radius 1 }";

SceneDesc parse(const std::string& text) { return parse_scene(text, "s.txt"); }

// A scene with the standard camera, one material, and a root group holding `body`.
std::string scene_with_group(int num_objects, const std::string& body) {
    return kCamera + kOneMaterial + "Group { numObjects " + std::to_string(num_objects) + "\nMaterialIndex 0\n" +
           body + "\n}\n";
}

std::string located(const Diagnostic& d) {
    return d.location.file + ":" + std::to_string(d.location.line) + ":" + std::to_string(d.location.column) + ": " +
           d.message;
}

// "file:line:col: message" for every diagnostic parse_scene throws, one a line; "" (and a
// failure) when it does not throw.
std::string errors_of(const std::string& text) {
    try {
        parse(text);
    } catch (const InputError& error) {
        std::string out;
        for (const Diagnostic& d : error.diagnostics()) out += located(d) + "\n";
        return out;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return "";
}

// The matrix of `Transform { <items> Sphere }` as the parser composes it.
Mat4 transform_of(const std::string& items) {
    const SceneDesc desc = parse(scene_with_group(1, "Transform { " + items + " " + kUnitSphere + " }"));
    const ObjectDesc& transform = desc.root->children.at(0);
    EXPECT_EQ(transform.kind, ObjectDesc::Kind::Transform);
    EXPECT_EQ(transform.children.size(), 1u);
    return transform.world_from_object;
}

::testing::AssertionResult near(Vec3f actual, Vec3f expected, float tolerance = 1e-5f) {
    if (std::fabs(actual.x - expected.x) <= tolerance && std::fabs(actual.y - expected.y) <= tolerance &&
        std::fabs(actual.z - expected.z) <= tolerance)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "got (" << actual.x << ", " << actual.y << ", " << actual.z
                                         << "), expected (" << expected.x << ", " << expected.y << ", "
                                         << expected.z << ")";
}

// Where `Transform { <items> ... }` puts the object-space point p.
Vec3f map(const std::string& items, Vec3f p) { return transform_point(transform_of(items), p); }

// ---- camera -------------------------------------------------------------------------------------

// Windows editors may save "UTF-8 with BOM": the mark is not part of the first keyword (it was
// read as one, 'unknown keyword' naming an invisible word), and columns count from after it.
TEST(ParseSceneTest, AUtf8ByteOrderMarkIsSkipped) {
    const std::string bom = "\xEF\xBB\xBF";
    const SceneDesc with_mark = parse(bom + scene_with_group(1, kUnitSphere));
    ASSERT_TRUE(with_mark.camera.has_value());
    EXPECT_EQ(with_mark.camera->width, 20);
    EXPECT_EQ(with_mark.root->children.size(), 1u);
    EXPECT_EQ(parse(bom + "# a comment first\n" + scene_with_group(1, kUnitSphere)).root->children.size(), 1u);
    try {
        parse(bom + "PerspectiveCamera { angle x }");
        ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
        ASSERT_FALSE(error.diagnostics().empty());
        const Diagnostic& d = error.diagnostics()[0];
        EXPECT_EQ(d.location.line, 1);
        EXPECT_EQ(d.location.column, 27);  // of the 'x', as an editor counts it
        EXPECT_EQ(d.source_line, "PerspectiveCamera { angle x }");
    }
}

// Classic Mac OS ended lines with CR alone: read by LF, a file starting with a comment was all
// comment ("the scene has no camera"). Lines and columns are an editor's; a DOS end mark (Ctrl-Z)
// last is no part of the scene.
TEST(ParseSceneTest, ClassicMacLineBreaksAndADosEndMarkAreRead) {
    std::string mac = "# a comment first\n" + scene_with_group(1, kUnitSphere);
    std::replace(mac.begin(), mac.end(), '\n', '\r');
    const SceneDesc desc = parse(mac);
    ASSERT_TRUE(desc.camera.has_value());
    EXPECT_EQ(desc.camera->width, 20);
    EXPECT_EQ(desc.root->children.size(), 1u);
    EXPECT_EQ(parse(scene_with_group(1, kUnitSphere) + "\x1a").root->children.size(), 1u);
    try {
        parse("# first\r\rPerspectiveCamera { angle x }\r");
        ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
        ASSERT_FALSE(error.diagnostics().empty());
        const Diagnostic& d = error.diagnostics()[0];
        EXPECT_EQ(d.location.line, 3);
        EXPECT_EQ(d.location.column, 27);
        EXPECT_EQ(d.source_line, "PerspectiveCamera { angle x }");
    }
}

TEST(ParseSceneTest, ReadsThePerspectiveCameraAsWritten) {
    const SceneDesc desc = parse(
        "PerspectiveCamera { center 13 11 30 direction -.16 -.12 -.5 up 0 1 0 angle 30 width 200 height 100 }\n"
        "Group { numObjects 0 }");
    ASSERT_TRUE(desc.camera);
    const CameraDesc& c = *desc.camera;
    EXPECT_EQ(c.kind, CameraDesc::Kind::Perspective);
    EXPECT_EQ(c.center, Vec3f(13, 11, 30));
    EXPECT_EQ(c.direction, Vec3f(-.16f, -.12f, -.5f));  // kept as written: not normalised here
    EXPECT_EQ(c.up, Vec3f(0, 1, 0));
    EXPECT_EQ(c.angle_degrees, 30.0f);  // degrees, as in the file
    EXPECT_EQ(c.width, 200);
    EXPECT_EQ(c.height, 100);
    EXPECT_EQ(c.location.line, 1);
    EXPECT_EQ(c.location.column, 1);
    EXPECT_TRUE(desc.warnings.empty());
}

TEST(ParseSceneTest, CameraFieldsMayComeInAnyOrder) {
    const SceneDesc desc = parse(
        "PerspectiveCamera { height 7 angle 45 up 0 0 1 width 9 direction 1 0 0 center 1 2 3 }\n"
        "Group { numObjects 0 }");
    const CameraDesc& c = *desc.camera;
    EXPECT_EQ(c.center, Vec3f(1, 2, 3));
    EXPECT_EQ(c.direction, Vec3f(1, 0, 0));
    EXPECT_EQ(c.up, Vec3f(0, 0, 1));
    EXPECT_EQ(c.angle_degrees, 45.0f);
    EXPECT_EQ(c.width, 9);
    EXPECT_EQ(c.height, 7);
}

TEST(ParseSceneTest, MitPerspectiveCameraMayLeaveOutTheImageSize) {
    const SceneDesc desc =
        parse("PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 }\nGroup { numObjects 0 }");
    EXPECT_EQ(desc.camera->width, 0);
    EXPECT_EQ(desc.camera->height, 0);
}

TEST(ParseSceneTest, ReadsTheMitOrthographicCamera) {
    const SceneDesc desc =
        parse("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\nGroup { numObjects 0 }");
    ASSERT_TRUE(desc.camera);
    EXPECT_EQ(desc.camera->kind, CameraDesc::Kind::Orthographic);
    EXPECT_EQ(desc.camera->size, 5.0f);
    EXPECT_EQ(desc.camera->width, 0);
}

TEST(ParseSceneTest, ALaterCameraReplacesTheEarlierOneWithAWarning) {
    const SceneDesc desc = parse(kCamera + "\nPerspectiveCamera { center 1 1 1 direction 0 0 -1 up 0 1 0 angle 60 }\n" +
                                 "Group { numObjects 0 }");
    EXPECT_EQ(desc.camera->center, Vec3f(1, 1, 1));
    EXPECT_EQ(desc.camera->angle_degrees, 60.0f);
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:3:1: this camera replaces the one at line 1");
    EXPECT_EQ(desc.warnings[0].severity, Severity::Warning);
}

// ---- background -----------------------------------------------------------------------------------

TEST(ParseSceneTest, BackgroundDefaultsToMidGreyAndNoAmbient) {
    const SceneDesc desc = parse(kCamera + "Group { numObjects 0 }");
    EXPECT_EQ(desc.background, Vec3f(0.5f, 0.5f, 0.5f));
    EXPECT_FALSE(desc.ambient);
    EXPECT_FALSE(desc.has_lights_block);
    EXPECT_TRUE(desc.lights.empty());
    EXPECT_TRUE(desc.materials.empty());
}

TEST(ParseSceneTest, ReadsTheBackgroundColourEvenAfterMaterials) {
    // scene07 puts Background after Materials; top-level blocks come in any order.
    const SceneDesc desc =
        parse(kOneMaterial + "Background { color 0.1 0.7 0.2 }\n" + kCamera + "Group { numObjects 0 }");
    EXPECT_EQ(desc.background, Vec3f(0.1f, 0.7f, 0.2f));
}

TEST(ParseSceneTest, ALaterBackgroundReplacesTheEarlierOneWithAWarning) {
    // What the second block leaves out is the default again: no ambient light from the first.
    const SceneDesc desc = parse(kCamera + "Background { color 0 0 0 ambientLight 0.5 0.5 0.5 }\n" +
                                 "Background { color 1 1 1 }\nGroup { numObjects 0 }");
    EXPECT_EQ(desc.background, Vec3f(1, 1, 1));
    EXPECT_FALSE(desc.ambient);
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:3:1: this Background block replaces the one at line 2");
    const SceneDesc colour_only = parse(kCamera + "Background { ambientLight 0.2 0.2 0.2 color 0 0 1 }\n" +
                                        "Background { ambientLight 0.1 0.1 0.1 }\nGroup { numObjects 0 }");
    EXPECT_EQ(colour_only.background, Vec3f(0.5f, 0.5f, 0.5f));
    EXPECT_EQ(colour_only.ambient.value_or(Vec3f(-1, -1, -1)), Vec3f(0.1f, 0.1f, 0.1f));
}

TEST(ParseSceneTest, ReadsTheMitAmbientLightInAnyOrder) {
    const SceneDesc desc =
        parse(kCamera + "Background { ambientLight 0.1 0.2 0.3 color 0 0 1 }\nGroup { numObjects 0 }");
    EXPECT_EQ(desc.background, Vec3f(0, 0, 1));
    ASSERT_TRUE(desc.ambient);
    EXPECT_EQ(*desc.ambient, Vec3f(0.1f, 0.2f, 0.3f));
}

TEST(ParseSceneTest, AnEmptyBackgroundBlockKeepsTheDefault) {
    EXPECT_EQ(parse(kCamera + "Background { }\nGroup { numObjects 0 }").background, Vec3f(0.5f, 0.5f, 0.5f));
}

// ---- lights -------------------------------------------------------------------------------------

TEST(ParseSceneTest, ReadsDirectionalAndPointLightsInOrder) {
    const SceneDesc desc = parse(kCamera +
                                 "Lights { numLights 2\n"
                                 "  DirectionalLight { direction -0.5 -0.3 -1 color 0.9 0.9 0.9 }\n"
                                 "  PointLight { color 0.8 0.8 0.4 position 0 5 5 }\n"
                                 "}\nGroup { numObjects 0 }");
    EXPECT_TRUE(desc.has_lights_block);
    ASSERT_EQ(desc.lights.size(), 2u);
    EXPECT_EQ(desc.lights[0].kind, LightDesc::Kind::Directional);
    EXPECT_EQ(desc.lights[0].direction, Vec3f(-0.5f, -0.3f, -1));  // not normalised here
    EXPECT_EQ(desc.lights[0].color, Vec3f(0.9f, 0.9f, 0.9f));
    EXPECT_EQ(desc.lights[0].location.line, 3);
    EXPECT_EQ(desc.lights[0].location.column, 3);
    EXPECT_EQ(desc.lights[1].kind, LightDesc::Kind::Point);
    EXPECT_EQ(desc.lights[1].position, Vec3f(0, 5, 5));
    EXPECT_EQ(desc.lights[1].color, Vec3f(0.8f, 0.8f, 0.4f));
    // The course has no attenuation: the default is constant 1, i.e. none.
    EXPECT_EQ(desc.lights[1].attenuation, Vec3f(1, 0, 0));
}

TEST(ParseSceneTest, ReadsTheMitPointLightAttenuation) {
    const SceneDesc desc = parse(kCamera +
                                 "Lights { numLights 1 PointLight { position 0 2.5 0 attenuation 0 0.2 0.05 "
                                 "color 1 1 1 } }\nGroup { numObjects 0 }");
    EXPECT_EQ(desc.lights.at(0).attenuation, Vec3f(0, 0.2f, 0.05f));
}

TEST(ParseSceneTest, ZeroLightsIsAValidBlock) {
    const SceneDesc desc = parse(kCamera + "Lights { numLights 0 }\nGroup { numObjects 0 }");
    EXPECT_TRUE(desc.has_lights_block);
    EXPECT_TRUE(desc.lights.empty());
}

// ---- materials ----------------------------------------------------------------------------------

TEST(ParseSceneTest, MaterialFieldsDefaultAsTheCourseSays) {
    const SceneDesc desc = parse(kCamera + "Materials { numMaterials 2 Material { } PhongMaterial { } }\n" +
                                 "Group { numObjects 0 }");
    ASSERT_EQ(desc.materials.size(), 2u);
    for (const MaterialDesc& m : desc.materials) {
        EXPECT_EQ(m.diffuse, Vec3f(1, 1, 1));
        EXPECT_EQ(m.specular, Vec3f(0, 0, 0));
        EXPECT_FALSE(m.shininess);  // unset: the course's 0 (or MIT's default) is applied by profile later
        EXPECT_EQ(m.texture, "");
        EXPECT_EQ(m.reflective, Vec3f(0, 0, 0));
        EXPECT_EQ(m.transparent, Vec3f(0, 0, 0));
        EXPECT_EQ(m.index_of_refraction, 1.0f);
    }
    EXPECT_EQ(desc.materials[1].location.column, 41);  // "PhongMaterial" after "...Material { } "
}

TEST(ParseSceneTest, MaterialFieldsMayComeInAnyOrderAndTextureIsKept) {
    // scene01 writes `shininess 20}` with the brace glued on.
    const SceneDesc desc = parse(kCamera +
                                 "Materials { numMaterials 1\n"
                                 "  PhongMaterial { shininess 20 texture tex/wood.bmp specularColor 1 1 1 "
                                 "diffuseColor 0.79 0.66 0.44 }\n"
                                 "}\n"
                                 "Materials { numMaterials 1 Material { diffuseColor 1 0 0 shininess 20} }\n"
                                 "Group { numObjects 0 }");
    // The second Materials block replaced the first, with a warning.
    ASSERT_EQ(desc.materials.size(), 1u);
    EXPECT_EQ(desc.materials[0].diffuse, Vec3f(1, 0, 0));
    EXPECT_EQ(desc.materials[0].shininess.value_or(-1), 20.0f);
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:5:1: this Materials block replaces the earlier one");

    const SceneDesc first = parse(kCamera +
                                  "Materials { numMaterials 1 PhongMaterial { shininess 20 texture tex/wood.bmp "
                                  "specularColor 1 1 1 diffuseColor 0.79 0.66 0.44 } }\nGroup { numObjects 0 }");
    const MaterialDesc& m = first.materials.at(0);
    EXPECT_EQ(m.diffuse, Vec3f(0.79f, 0.66f, 0.44f));
    EXPECT_EQ(m.specular, Vec3f(1, 1, 1));
    EXPECT_EQ(m.shininess.value_or(-1), 20.0f);
    EXPECT_EQ(m.texture, "tex/wood.bmp");
}

TEST(ParseSceneTest, ReadsTheMitMaterialFields) {
    const SceneDesc desc = parse(kCamera +
                                 "Materials { numMaterials 1 PhongMaterial {\n"
                                 "  diffuseColor 0.1 0.1 0.1 specularColor 1 1 1 exponent 50\n"
                                 "  transparentColor 0.5 0.6 0.7 reflectiveColor 0.9 0.8 0.7 indexOfRefraction 1.5\n"
                                 "} }\nGroup { numObjects 0 }");
    const MaterialDesc& m = desc.materials.at(0);
    EXPECT_EQ(m.diffuse, Vec3f(0.1f, 0.1f, 0.1f));
    EXPECT_EQ(m.specular, Vec3f(1, 1, 1));
    EXPECT_EQ(m.shininess.value_or(-1), 50.0f);  // `exponent` is MIT's name for shininess
    EXPECT_EQ(m.transparent, Vec3f(0.5f, 0.6f, 0.7f));
    EXPECT_EQ(m.reflective, Vec3f(0.9f, 0.8f, 0.7f));
    EXPECT_EQ(m.index_of_refraction, 1.5f);
}

TEST(ParseSceneTest, ShininessAndExponentTogetherAreAnError) {
    EXPECT_EQ(errors_of(kCamera + "Materials { numMaterials 1 Material { shininess 2 exponent 3 } }\n" +
                        "Group { numObjects 0 }"),
              "s.txt:2:62: give 'shininess' or 'exponent', not both\n");
}

TEST(ParseSceneTest, AFieldGivenTwiceKeepsTheLastValueWithAWarningAtBothPlaces) {
    // The course's starter reads fields in a loop, so the last value wins.
    const SceneDesc desc = parse(kCamera +
                                 "Materials { numMaterials 1\n"
                                 "Material { diffuseColor 1 0 0\n"
                                 "  specularColor 1 1 1 diffuseColor 0 1 0 }\n"
                                 "}\n" +
                                 "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 radius 2 } }\n");
    EXPECT_EQ(desc.materials.at(0).diffuse, Vec3f(0, 1, 0));
    EXPECT_EQ(desc.root->children.at(0).sphere.radius, 2);
    ASSERT_EQ(desc.warnings.size(), 4u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:4:23: 'diffuseColor' is given twice in Material: the last value is used");
    EXPECT_EQ(desc.warnings[0].severity, Severity::Warning);
    EXPECT_EQ(located(desc.warnings[1]), "s.txt:3:12: the first value was given here");
    EXPECT_EQ(desc.warnings[1].severity, Severity::Note);
    EXPECT_EQ(located(desc.warnings[2]), "s.txt:6:69: 'radius' is given twice in Sphere: the last value is used");
    EXPECT_EQ(located(desc.warnings[3]), "s.txt:6:60: the first value was given here");
    // The caret display shows each line.
    EXPECT_EQ(desc.warnings[1].source_line, "Material { diffuseColor 1 0 0");
}

TEST(ParseSceneTest, AMeshPathMayBeQuotedAndThenHoldSpaces) {
    const SceneDesc desc = parse(scene_with_group(3,
                                                  "TriangleMesh { obj_file \"mesh/my model.obj\" }\n"
                                                  "TriangleMesh { obj_file \"plain.obj\" }\n"
                                                  "TriangleMesh { obj_file \"odd {#} name.obj\"}"));
    ASSERT_EQ(desc.root->children.size(), 3u);
    EXPECT_EQ(desc.root->children[0].mesh_path, "mesh/my model.obj");
    EXPECT_EQ(desc.root->children[1].mesh_path, "plain.obj");
    EXPECT_EQ(desc.root->children[2].mesh_path, "odd {#} name.obj");
    // The location is the opening quote's.
    EXPECT_EQ(desc.root->children[0].mesh_path_location.line, 5);
    EXPECT_EQ(desc.root->children[0].mesh_path_location.column, 25);
}

TEST(ParseSceneTest, AnUnterminatedOrEmptyQuotedPathIsALocatedError) {
    // The quoted name runs to the end of its line, taking the '}' with it: the error is at the quote,
    // and the Group is left one brace short.
    EXPECT_EQ(errors_of(scene_with_group(1, "TriangleMesh { obj_file \"mesh/my model.obj }\n")),
              "s.txt:5:25: the file name's quote is not closed: add a '\"' before the end of the line\n"
              "s.txt:8:1: unexpected end of file: 'Group' opened at line 3 is not closed\n");
    EXPECT_EQ(errors_of(scene_with_group(1, "TriangleMesh { obj_file \"\" }")),
              "s.txt:5:25: the file name for 'obj_file' is empty\n");
}

// ---- groups and primitives --------------------------------------------------------------------------

TEST(ParseSceneTest, ReadsEveryPrimitiveWithItsFieldsInAnyOrder) {
    const SceneDesc desc = parse(scene_with_group(4,
                                                  "Sphere { radius 0.75 center 1 -1 -1 }\n"
                                                  "Plane { offset -2 normal 0 1 0 }\n"
                                                  "Triangle { vertex2 0 1 0 vertex0 0 0 0 vertex1 1 0 0 }\n"
                                                  "TriangleMesh { obj_file mesh/cube.obj }"));
    ASSERT_TRUE(desc.root);
    const ObjectDesc& root = *desc.root;
    EXPECT_EQ(root.kind, ObjectDesc::Kind::Group);
    ASSERT_EQ(root.children.size(), 4u);
    const ObjectDesc& sphere = root.children[0];
    EXPECT_EQ(sphere.kind, ObjectDesc::Kind::Sphere);
    EXPECT_EQ(sphere.sphere.center, Vec3f(1, -1, -1));
    EXPECT_EQ(sphere.sphere.radius, 0.75f);
    EXPECT_EQ(sphere.location.line, 5);  // camera 1, materials 2, group 3, MaterialIndex 4
    EXPECT_EQ(sphere.location.column, 1);
    const ObjectDesc& plane = root.children[1];
    EXPECT_EQ(plane.kind, ObjectDesc::Kind::Plane);
    EXPECT_EQ(plane.plane.normal, Vec3f(0, 1, 0));
    EXPECT_EQ(plane.plane.offset, -2.0f);
    const ObjectDesc& triangle = root.children[2];
    EXPECT_EQ(triangle.kind, ObjectDesc::Kind::Triangle);
    EXPECT_EQ(triangle.vertices[0], Vec3f(0, 0, 0));
    EXPECT_EQ(triangle.vertices[1], Vec3f(1, 0, 0));
    EXPECT_EQ(triangle.vertices[2], Vec3f(0, 1, 0));
    const ObjectDesc& mesh = root.children[3];
    EXPECT_EQ(mesh.kind, ObjectDesc::Kind::TriangleMesh);
    EXPECT_EQ(mesh.mesh_path, "mesh/cube.obj");
    EXPECT_EQ(mesh.mesh, -1);  // parse_scene does not load meshes
    EXPECT_EQ(mesh.mesh_path_location.line, 8);
    EXPECT_EQ(mesh.mesh_path_location.column, 25);
    for (const ObjectDesc& object : root.children) EXPECT_EQ(object.material, 0);
    EXPECT_TRUE(desc.meshes.empty());
}

TEST(ParseSceneTest, NumObjectsCountsObjectsButNotMaterialIndexLines) {
    const SceneDesc desc = parse(kCamera + "Materials { numMaterials 3 Material { } Material { } Material { } }\n" +
                                 "Group { numObjects 2\n"
                                 "  MaterialIndex 0 MaterialIndex 1 " + kUnitSphere + "\n"
                                 "  MaterialIndex 2 Group { numObjects 1 " + kUnitSphere + " }\n"
                                 "}\n");
    ASSERT_EQ(desc.root->children.size(), 2u);
    EXPECT_EQ(desc.root->children[0].material, 1);  // the last MaterialIndex before it wins
    // A nested group counts as one object of its parent.
    EXPECT_EQ(desc.root->children[1].kind, ObjectDesc::Kind::Group);
    ASSERT_EQ(desc.root->children[1].children.size(), 1u);
    EXPECT_EQ(desc.root->children[1].children[0].material, 2);
}

TEST(ParseSceneTest, MaterialIndexStaysInForceOutOfNestedGroupsAsInTheCourse) {
    // scene04: the inner group leaves material 2 current; the outer group's next object without its
    // own MaterialIndex gets it, and a later MaterialIndex 3 switches for everything after it.
    const SceneDesc desc = parse(kCamera +
                                 "Materials { numMaterials 4 Material { } Material { } Material { } Material { } }\n"
                                 "Group { numObjects 4\n"
                                 "  MaterialIndex 0\n"
                                 "  Group { numObjects 2 MaterialIndex 1 " + kUnitSphere + " MaterialIndex 2 " +
                                 kUnitSphere + " }\n"
                                 "  " + kUnitSphere + "\n"
                                 "  Transform { Translate 1 0 0 " + kUnitSphere + " }\n"
                                 "  MaterialIndex 3 Transform { Group { numObjects 1 " + kUnitSphere + " } }\n"
                                 "}\n");
    const ObjectDesc& root = *desc.root;
    ASSERT_EQ(root.children.size(), 4u);
    EXPECT_EQ(root.children[0].children.at(0).material, 1);
    EXPECT_EQ(root.children[0].children.at(1).material, 2);
    EXPECT_EQ(root.children[1].material, 2);               // carried out of the inner group
    EXPECT_EQ(root.children[2].children.at(0).material, 2);  // and into a Transform
    EXPECT_EQ(root.children[3].children.at(0).children.at(0).material, 3);
}

TEST(ParseSceneTest, MaterialIndexIsCarriedFromOneTopLevelGroupToTheNext) {
    // Not scoped at all: a second Group (which replaces the first, with a warning) keeps it too.
    const SceneDesc desc = parse(kCamera + "Materials { numMaterials 2 Material { } Material { } }\n" +
                                 "Group { numObjects 1 MaterialIndex 1 " + kUnitSphere + " }\n" +
                                 "Group { numObjects 1 " + kUnitSphere + " }\n");
    EXPECT_EQ(desc.root->location.line, 4);
    EXPECT_EQ(desc.root->children.at(0).material, 1);
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:4:1: this Group replaces the one at line 3");
}

TEST(ParseSceneTest, AnEmptyGroupIsAValidScene) {
    const SceneDesc desc = parse(kCamera + "Group { numObjects 0 }");
    ASSERT_TRUE(desc.root);
    EXPECT_TRUE(desc.root->children.empty());
}

TEST(ParseSceneTest, MaterialIndexEqualToTheCountIsRejectedUnlikeTheCoursesOffByOne) {
    EXPECT_EQ(errors_of(kCamera + kOneMaterial + "Group { numObjects 0 MaterialIndex 1 }"),
              "s.txt:3:36: material index 1 is out of range: the scene has 1 material (index 0)\n");
}

TEST(ParseSceneTest, ADegenerateTriangleIsAWarningNotAnError) {
    const SceneDesc desc =
        parse(scene_with_group(1, "Triangle { vertex0 0 0 0 vertex1 1 1 1 vertex2 2 2 2 }"));
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]),
              "s.txt:5:1: degenerate triangle: its vertices are on one line, so it is never seen");
}

TEST(ParseSceneTest, CommentsAndCrlfAndTabsAreIgnored) {
    const SceneDesc desc = parse(
        "# a comment before everything\r\n"
        "PerspectiveCamera {\t# the camera\r\n"
        "\tcenter 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 4 height 4\r\n"
        "}\r\n"
        "Materials { numMaterials 1 Material { diffuseColor 1 0 0 } } # red\r\n"
        "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 2} }\r\n");
    EXPECT_EQ(desc.camera->width, 4);
    EXPECT_EQ(desc.materials.at(0).diffuse, Vec3f(1, 0, 0));
    EXPECT_EQ(desc.root->children.at(0).sphere.radius, 2.0f);
    EXPECT_EQ(desc.root->children.at(0).location.line, 6);
    EXPECT_EQ(desc.root->children.at(0).location.column, 38);
}

TEST(ParseSceneTest, ABinaryFileIsOneErrorAtItsFirstBadByte) {
    // Not a cascade of unknown keywords: one error at the first byte that no text holds (the rule
    // of sceneio/text_check.h), here the NUL of a file cut into a scene.
    EXPECT_EQ(errors_of(kCamera + std::string("Group {\0\x01\x02}", 11)),
              "s.txt:2:8: this is not a text file: byte 0x00 (NUL) never appears in text\n");
    EXPECT_EQ(errors_of(kCamera + "\x1b[1mGroup { }\n"),
              "s.txt:2:1: this is not a text file: byte 0x1b is a control character at the start of a line\n");
}

TEST(ParseSceneTest, KeepsTheTextForTheLinesOfLaterErrors) {
    const std::string text = scene_with_group(1, kUnitSphere);
    EXPECT_EQ(parse(text).source_text, text);
}

TEST(ParseSceneTest, GroupsNestUpToTheLimitButNotBeyond) {
    auto nested = [](int levels) {
        std::string text = kCamera;
        for (int i = 0; i < levels; ++i) text += "Group { numObjects " + std::string(i + 1 < levels ? "1" : "0") + "\n";
        for (int i = 0; i < levels; ++i) text += "}\n";
        return text;
    };
    const SceneDesc desc = parse(nested(kMaxNestingDepth));
    int depth = 0;
    for (const ObjectDesc* g = &*desc.root; g; g = g->children.empty() ? nullptr : &g->children[0]) ++depth;
    EXPECT_EQ(depth, kMaxNestingDepth);
    // Group number 1001 is on line 1002 (the camera is line 1).
    EXPECT_EQ(errors_of(nested(kMaxNestingDepth + 1)),
              "s.txt:1002:1: groups and transforms are nested more than 1000 levels deep\n");
}

// ---- transforms -------------------------------------------------------------------------------------

TEST(ParseSceneTest, ATransformWithNoItemsIsTheIdentity) {
    EXPECT_TRUE(transform_of("").is_identity());
}

TEST(ParseSceneTest, ScaleScalesEachAxis) {
    EXPECT_TRUE(near(map("Scale 2 3 4", {1, 1, -1}), {2, 3, -4}));
}

TEST(ParseSceneTest, UniformScaleScalesAllAxes) {
    EXPECT_TRUE(near(map("UniformScale 3", {1, 2, 3}), {3, 6, 9}));
}

TEST(ParseSceneTest, TranslateMovesPoints) {
    EXPECT_TRUE(near(map("Translate 5 -6 .5", {1, 1, 1}), {6, -5, 1.5f}));
    // ...but not directions.
    EXPECT_TRUE(near(transform_vector(transform_of("Translate 5 -6 .5"), {1, 1, 1}), {1, 1, 1}));
}

TEST(ParseSceneTest, AxisRotationsAreRightHandedAndInDegrees) {
    // Counter-clockwise seen from the axis tip: X takes y to z, Y takes z to x, Z takes x to y.
    EXPECT_TRUE(near(map("XRotate 90", {0, 1, 0}), {0, 0, 1}));
    EXPECT_TRUE(near(map("YRotate 90", {0, 0, 1}), {1, 0, 0}));
    EXPECT_TRUE(near(map("ZRotate 90", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("ZRotate -90", {1, 0, 0}), {0, -1, 0}));
    // 45 degrees about z: (1, 0, 0) -> (cos 45, sin 45, 0).
    EXPECT_TRUE(near(map("ZRotate 45", {1, 0, 0}), {0.70710678f, 0.70710678f, 0}));
}

TEST(ParseSceneTest, RotateTakesAnAxisThatNeedNotBeUnitLength) {
    EXPECT_TRUE(near(map("Rotate { 0 0 2 90 }", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("Rotate { 0 0 -1 90 }", {1, 0, 0}), {0, -1, 0}));
    // 120 degrees about (1, 1, 1) cycles the axes x -> y -> z -> x (Rodrigues by hand: c = -1/2,
    // s = sqrt(3)/2, k = 3/2 give the column for x as (0, 1, 0)).
    EXPECT_TRUE(near(map("Rotate { 1 1 1 120 }", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("Rotate { 1 1 1 120 }", {0, 0, 1}), {1, 0, 0}));
    // Axes whose squared length underflows float are not zero (fuzz_render_pipeline found the
    // parser refusing them): the smallest normal float, a subnormal, and the largest float.
    EXPECT_TRUE(near(map("Rotate { 0 0 1.17549435e-38 90 }", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("Rotate { 1.17549435e-38 1.17549435e-38 1.17549435e-38 120 }", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("Rotate { 0 0 1e-45 90 }", {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(map("Rotate { 0 0 3.4e38 90 }", {1, 0, 0}), {0, 1, 0}));
}

TEST(ParseSceneTest, TheLastListedItemAppliesToTheObjectFirst) {
    // scene04's bars: Translate 5 0 0, Scale 5 0.2 0.2: the cube corner (1, 1, 1) is scaled to
    // (5, 0.2, 0.2) and then moved to (10, 0.2, 0.2).
    EXPECT_TRUE(near(map("Translate 5 0 0 Scale 5 0.2 0.2", {1, 1, 1}), {10, 0.2f, 0.2f}));
    // scene06: Scale 5 5 5, Translate 0.03 -0.0666 0: moved first, then scaled about the origin.
    EXPECT_TRUE(near(map("Scale 5 5 5 Translate 0.03 -0.0666 0", {0, 0, 0}), {0.15f, -0.333f, 0}));
    // Three items on (1, 1, 0): Scale 2 1 1 -> (2, 1, 0); ZRotate 90 takes (x, y) to (-y, x) ->
    // (-1, 2, 0); Translate 1 2 3 -> (0, 4, 3).
    EXPECT_TRUE(near(map("Translate 1 2 3 ZRotate 90 Scale 2 1 1", {1, 1, 0}), {0, 4, 3}));
    // The same items listed the other way: (2, 3, 3) -> (-3, 2, 3) -> (-6, 2, 3).
    EXPECT_TRUE(near(map("Scale 2 1 1 ZRotate 90 Translate 1 2 3", {1, 1, 0}), {-6, 2, 3}));
}

TEST(ParseSceneTest, Matrix4fListsColumns) {
    // Columns (0, 1, 0, 0), (-1, 0, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1): x -> y and y -> -x, i.e.
    // ZRotate 90. Read as rows it would be ZRotate -90.
    EXPECT_TRUE(near(map("Matrix4f { 0 1 0 0  -1 0 0 0  0 0 1 0  0 0 0 1 }", {1, 0, 0}), {0, 1, 0}));
    // The translation is the last four numbers (column 3).
    EXPECT_TRUE(near(map("Matrix4f { 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 }", {1, 2, 3}), {6, 8, 10}));
}

TEST(ParseSceneTest, Matrix4fComposesOnTheOtherSide) {
    // Scale 2 2 2 then Matrix4f (translate 5 6 7): M = T·S, so (1, 0, 0) -> (2, 0, 0) -> (7, 6, 7).
    // With an ordinary `Translate 5 6 7` in its place: M = S·T, so (1, 0, 0) -> (6, 6, 7) -> (12, 12, 14).
    EXPECT_TRUE(near(map("Scale 2 2 2 Matrix4f { 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 }", {1, 0, 0}), {7, 6, 7}));
    EXPECT_TRUE(near(map("Scale 2 2 2 Translate 5 6 7", {1, 0, 0}), {12, 12, 14}));
    // Two Matrix4f: M = B·A, so the first listed (A: translate 1 0 0) applies first, then B (scale 2):
    // the origin goes to (1, 0, 0) and then to (2, 0, 0).
    EXPECT_TRUE(near(map("Matrix4f { 1 0 0 0  0 1 0 0  0 0 1 0  1 0 0 1 } "
                         "Matrix4f { 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 }",
                         {0, 0, 0}),
                     {2, 0, 0}));
}

TEST(ParseSceneTest, MitMatrixListsRowsAndAlsoComposesOnTheOtherSide) {
    // The same 16 numbers as the Matrix4f test, read row by row: x -> -y (ZRotate -90).
    EXPECT_TRUE(near(map("Matrix { 0 1 0 0  -1 0 0 0  0 0 1 0  0 0 0 1 }", {1, 0, 0}), {0, -1, 0}));
    EXPECT_TRUE(near(map("Matrix { 1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1 }", {1, 2, 3}), {6, 8, 10}));
    // MIT's parser does matrix = file_matrix * matrix, like the course's Matrix4f.
    EXPECT_TRUE(near(map("Scale 2 2 2 Matrix { 1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1 }", {1, 0, 0}), {7, 6, 7}));
}

TEST(ParseSceneTest, TransformsNestAndHoldAnyObject) {
    // MIT's crazy_transforms style: a Transform around a Group around Transforms.
    const SceneDesc desc = parse(scene_with_group(
        1, "Transform { UniformScale 2 Group { numObjects 2\n"
           "  Transform { Translate 1 0 0 Transform { ZRotate 90 TriangleMesh { obj_file cube.obj } } }\n"
           "  Transform { Plane { normal 0 1 0 offset 0 } } } }"));
    const ObjectDesc& outer = desc.root->children.at(0);
    EXPECT_EQ(outer.kind, ObjectDesc::Kind::Transform);
    const ObjectDesc& group = outer.children.at(0);
    EXPECT_EQ(group.kind, ObjectDesc::Kind::Group);
    ASSERT_EQ(group.children.size(), 2u);
    const ObjectDesc& inner = group.children[0].children.at(0);
    EXPECT_EQ(inner.kind, ObjectDesc::Kind::Transform);
    EXPECT_EQ(inner.children.at(0).kind, ObjectDesc::Kind::TriangleMesh);
    EXPECT_EQ(inner.children.at(0).mesh_path, "cube.obj");
    // Each Transform stores only its own matrix; the outer one is not folded in.
    EXPECT_TRUE(near(transform_point(inner.world_from_object, {1, 0, 0}), {0, 1, 0}));
    EXPECT_TRUE(near(transform_point(group.children[0].world_from_object, {0, 0, 0}), {1, 0, 0}));
    EXPECT_TRUE(near(transform_point(outer.world_from_object, {1, 1, 1}), {2, 2, 2}));
}

// ---- curves and surfaces of revolution (the course's next assignment) ----------------------------

TEST(ParseSceneTest, ReadsCurvesAndSurfacesOfRevolutionWhereverAnObjectMayStand) {
    const SceneDesc desc = parse(scene_with_group(
        3, "BezierCurve { controls [ 3 0 0 ] [ 3 1 0 ]\n [ 1 1 0 ] [ 1 0 0.5 ] }\n"
           "Transform { Translate 1 0 0 RevSurface { profile BsplineCurve { controls\n"
           "  [ -1 2 0 ] [ -2 1 0 ] [ -1.5 0 0 ] [ -.5 -1 0 ] [ 0 -1 0 ] } } }\n"
           "Group { numObjects 1 RevSurface { profile BezierCurve { controls [ 0 1 0 ] [ 1 1 0 ] [ 1 0 0 ] [ 2 -1 0 ] } } }"));
    const std::vector<ObjectDesc>& objects = desc.root->children;
    ASSERT_EQ(objects.size(), 3u);
    EXPECT_EQ(objects[0].kind, ObjectDesc::Kind::Curve);
    EXPECT_EQ(objects[0].curve.type, CurveType::Bezier);
    ASSERT_EQ(objects[0].curve.controls.size(), 4u);
    EXPECT_EQ(objects[0].curve.controls[3], (Vec3f{1, 0, 0.5f}));  // a curve alone may leave z = 0
    const ObjectDesc& surface = objects[1].children.at(0);
    EXPECT_EQ(surface.kind, ObjectDesc::Kind::RevSurface);
    EXPECT_EQ(surface.material, 0);
    EXPECT_EQ(surface.curve.type, CurveType::Bspline);
    ASSERT_EQ(surface.curve.controls.size(), 5u);
    EXPECT_EQ(surface.curve.controls[3], (Vec3f{-0.5f, -1, 0}));
    EXPECT_EQ(surface.location.line, 7);  // after the camera, materials, Group, MaterialIndex and the curve's two lines
    EXPECT_EQ(surface.location.column, 29);
    EXPECT_EQ(objects[2].children.at(0).kind, ObjectDesc::Kind::RevSurface);
    EXPECT_EQ(objects[2].children.at(0).curve.type, CurveType::Bezier);
}

TEST(ParseSceneTest, CurvesNeedNoMaterialAndAreNotDrawnWhichOneWarningSays) {
    // The course's scene08: curves only, no Materials block, no MaterialIndex.
    const SceneDesc desc = parse(kCamera + "Group { numObjects 3\n"
                                           "  BezierCurve { controls [ 0 0 0 ] [ 1 1 0 ] [ 2 1 0 ] [ 3 0 0 ] }\n"
                                           "  BsplineCurve { controls [ 0 0 0 ] [ 1 1 0 ] [ 2 1 0 ] [ 3 0 0 ] }\n"
                                           "  BsplineCurve { controls [ 0 0 1 ] [ 1 1 0 ] [ 2 1 0 ] [ 3 0 0 ] [ 4 0 0 ] }\n}\n");
    ASSERT_EQ(desc.root->children.size(), 3u);
    EXPECT_TRUE(desc.materials.empty());
    ASSERT_EQ(desc.warnings.size(), 1u);
    EXPECT_EQ(located(desc.warnings[0]), "s.txt:3:3: BezierCurve is a curve, not a surface: raycast draws nothing for "
                                         "it, as the course's ray caster does (3 curves in this file are not drawn)");
    // A RevSurface, like any surface, takes the current material and needs one.
    EXPECT_EQ(errors_of(kCamera + "Group { numObjects 1 RevSurface { profile BezierCurve { controls [ 0 1 0 ] [ 1 1 0 ] "
                                  "[ 1 0 0 ] [ 2 -1 0 ] } } }"),
              "s.txt:2:22: RevSurface has no material: put 'MaterialIndex i' before it\n");
}

TEST(ParseSceneTest, CurveMistakesAreLocated) {
    // Each body is the only object of a group whose first line is line 5; columns by hand.
    std::string many = "BezierCurve { controls";
    for (int i = 0; i < kMaxBezierControlPoints + 3; ++i) many += " [ " + std::to_string(i) + " 0 0 ]";
    const struct {
        std::string body, error;
    } cases[] = {
        // Too few points for the degree, and the Bezier counts the course's starter refuses (3k+1).
        {"BsplineCurve { controls [ 0 0 0 ] [ 1 0 0 ] [ 2 0 0 ] }",
         "5:1: a BsplineCurve of degree 3 needs at least 4 control points, got 3"},
        {"BezierCurve { controls [ 0 0 0 ] [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] [ 4 0 0 ] }",
         "5:1: a BezierCurve needs 3k+1 control points (4, 7, 10, ...), as the course's starter does, got 5"},
        {"BezierCurve { controls [ 0 0 0 ] [ 1 0 0 ] }",
         "5:1: a BezierCurve needs 3k+1 control points (4, 7, 10, ...), as the course's starter does, got 2"},
        {"BezierCurve { controls }",
         "5:1: a BezierCurve needs 3k+1 control points (4, 7, 10, ...), as the course's starter does, got 0"},
        {many + " }",
         "5:1: a BezierCurve may have at most 31 control points (degree 30), got 34: a BsplineCurve takes any number"},
        // A profile off the z = 0 plane, at the first point that leaves it.
        {"RevSurface { profile BezierCurve { controls [ 0 1 0 ] [ 1 1 0.5 ] [ 1 0 -1 ] [ 2 -1 0 ] } }",
         "5:61: the profile of a RevSurface must lie in the z = 0 plane (it is turned about the y axis), but this "
         "point has z = 0.5 (2 points are off the plane)"},
        // Brackets.
        {"BezierCurve { controls [ 0 0 0 [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:32: expected ']' to close the control point opened at line 5, column 24, got '['"},
        {"BezierCurve { controls 0 0 0 ] [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:24: expected '[' to start a control point, got '0'"},
        {"BezierCurve { controls [ 0 0 0 ] ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:34: unexpected ']': no control point is open (is a '[' missing?)"},
        {"BezierCurve { controls [0 0 0] [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:24: write '[' apart from the number after it: '[0' is read as one word"},
        {"BezierCurve { controls [ 0 0 0] [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:30: write ']' apart from the number before it: '0]' is read as one word"},
        {"BezierCurve { controls [ 0 0 ] [ 1 0 0 ] [ 2 0 0 ] [ 3 0 0 ] }",
         "5:30: a control point has three numbers, x y z: expected its z, got ']'"},
        // The profile's type and the fields.
        {"RevSurface { profile BezierCurv { controls [ 0 1 0 ] } }",
         "5:22: unknown profile 'BezierCurv'; did you mean 'BezierCurve'?"},
        {"RevSurface { profile Circle { radius 1 } }", "5:22: unknown profile 'Circle': expected BezierCurve or BsplineCurve"},
        {"RevSurface { }", "5:14: RevSurface is missing 'profile'"},
        {"BsplineCurve { control [ 0 0 0 ] }",
         "5:16: unknown field 'control' in BsplineCurve; did you mean 'controls'?\ns.txt:5:34: BsplineCurve is missing "
         "'controls'"},
    };
    for (const auto& c : cases) EXPECT_EQ(errors_of(scene_with_group(1, c.body)), "s.txt:" + c.error + "\n") << c.body;
}

// ---- a whole MIT 6.837 scene -----------------------------------------------------------------------

TEST(ParseSceneTest, ReadsAnMitSceneWithEveryMitForm) {
    const SceneDesc desc = parse(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n"
        "Lights { numLights 2\n"
        "  DirectionalLight { direction -0.2 -0.2 -0.8 color 0.9 0.9 0.9 }\n"
        "  PointLight { position 0 2.5 0 color 0.8 0.8 0.8 attenuation 0 0.2 0 }\n"
        "}\n"
        "Background { color 0.1 0.5 0.1 ambientLight 0.1 0.1 0.1 }\n"
        "Materials { numMaterials 2\n"
        "  Material { diffuseColor 1 0 0 }\n"
        "  PhongMaterial { diffuseColor 0 0 1 specularColor 1 1 1 exponent 50 reflectiveColor 0.9 0.9 0.9\n"
        "                  transparentColor 0 0 0 indexOfRefraction 1 }\n"
        "}\n"
        "Group { numObjects 3\n"
        "  MaterialIndex 0 Sphere { center 0 0 0 radius 1 }\n"
        "  MaterialIndex 1 Transform { Matrix { 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1 } UniformScale 0.5\n"
        "      TriangleMesh { obj_file cube.obj } }\n"
        "  Triangle { vertex0 0 0 0 vertex1 1 0 0 vertex2 0 1 0 }\n"
        "}\n");
    EXPECT_EQ(desc.camera->kind, CameraDesc::Kind::Orthographic);
    EXPECT_EQ(desc.lights.size(), 2u);
    EXPECT_EQ(desc.lights[1].attenuation, Vec3f(0, 0.2f, 0));
    EXPECT_EQ(*desc.ambient, Vec3f(0.1f, 0.1f, 0.1f));
    EXPECT_EQ(desc.materials.size(), 2u);
    EXPECT_EQ(desc.materials[1].reflective, Vec3f(0.9f, 0.9f, 0.9f));
    ASSERT_EQ(desc.root->children.size(), 3u);
    EXPECT_EQ(desc.root->children[0].material, 0);
    EXPECT_EQ(desc.root->children[1].children.at(0).material, 1);
    EXPECT_EQ(desc.root->children[2].material, 1);
    EXPECT_TRUE(near(transform_point(desc.root->children[1].world_from_object, {2, 2, 2}), {1, 1, 1}));
    EXPECT_TRUE(desc.warnings.empty());
}

// ---- every scene on disk -----------------------------------------------------------------------------

// Every TriangleMesh in the tree has a loaded mesh.
void expect_meshes_loaded(const ObjectDesc& object, const SceneDesc& desc, int& mesh_objects) {
    if (object.kind == ObjectDesc::Kind::TriangleMesh) {
        ++mesh_objects;
        ASSERT_GE(object.mesh, 0) << object.mesh_path;
        ASSERT_LT(object.mesh, static_cast<int>(desc.meshes.size()));
        EXPECT_GT(desc.meshes[static_cast<size_t>(object.mesh)].mesh.triangle_count(), 0u) << object.mesh_path;
    }
    for (const ObjectDesc& child : object.children) expect_meshes_loaded(child, desc, mesh_objects);
}

// Loads every .txt scene in `folder`; returns how many there were.
int load_every_scene_in(const std::string& folder) {
    std::vector<std::string> paths;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
        if (entry.path().extension() == ".txt") paths.push_back(entry.path().string());
    std::sort(paths.begin(), paths.end());
    for (const std::string& path : paths) {
        SCOPED_TRACE(path);
        try {
            // The mesh paths are relative: load_scene_file tries the scene's folder (MIT: cube.obj
            // beside the scene) and its parent (course: testcases/../mesh/cube.obj).
            const SceneDesc desc = load_scene_file(path);
            EXPECT_TRUE(desc.camera);
            EXPECT_TRUE(desc.root);
            EXPECT_FALSE(desc.materials.empty());
            int mesh_objects = 0;
            if (desc.root) expect_meshes_loaded(*desc.root, desc, mesh_objects);
            if (mesh_objects > 0) {
                EXPECT_FALSE(desc.meshes.empty());
            }
            for (const Diagnostic& w : desc.warnings) ADD_FAILURE() << "unexpected warning: " << format_diagnostic(w);
        } catch (const InputError& error) {
            ADD_FAILURE() << error.what();
        }
    }
    return static_cast<int>(paths.size());
}

TEST(ParseSceneFilesTest, AllSevenCourseScenesLoadWithoutErrors) {
    const std::string shared = test::shared_dir();
    if (shared.empty()) GTEST_SKIP() << "../shared is not here";
    EXPECT_EQ(load_every_scene_in(shared + "/course/testcases"), 7);
}

TEST(ParseSceneFilesTest, AllMitSceneFilesOfAssignmentsOneToFourLoadWithoutErrors) {
    const std::string shared = test::shared_dir();
    if (shared.empty()) GTEST_SKIP() << "../shared is not here";
    const std::string mit = shared + "/reference/mit6837-f04/";
    // 7 + 16 + 12 + 14 scene files (the README's "59" counts reference images, not scenes).
    EXPECT_EQ(load_every_scene_in(mit + "a1"), 7);
    EXPECT_EQ(load_every_scene_in(mit + "a2"), 16);
    EXPECT_EQ(load_every_scene_in(mit + "a3"), 12);
    EXPECT_EQ(load_every_scene_in(mit + "a4"), 14);
}

TEST(ParseSceneFilesTest, CourseScene04KeepsMaterialTwoForNothingButSwitchesToThree) {
    // The real scene04: bars get materials 0, 1, 2 and the tilted box gets 3, and the file's
    // `-.16 -.12 -.5` direction reads as three numbers.
    const std::string shared = test::shared_dir();
    if (shared.empty()) GTEST_SKIP() << "../shared is not here";
    const SceneDesc desc = load_scene_file(shared + "/course/testcases/scene04_axes.txt");
    EXPECT_EQ(desc.camera->direction, Vec3f(-.16f, -.12f, -.5f));
    const ObjectDesc& root = *desc.root;
    ASSERT_EQ(root.children.size(), 2u);
    const ObjectDesc& bars = root.children[0];
    ASSERT_EQ(bars.children.size(), 3u);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(bars.children[static_cast<size_t>(i)].children.at(0).material, i);
    EXPECT_EQ(root.children[1].children.at(0).material, 3);
    // Every use of mesh/cube.obj shares one loaded mesh of 12 triangles.
    ASSERT_EQ(desc.meshes.size(), 1u);
    EXPECT_EQ(desc.meshes[0].mesh.triangle_count(), 12u);
}

}  // namespace
}  // namespace raycast
