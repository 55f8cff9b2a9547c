#include "sceneio/load_obj.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "base/error.h"
#include "geometry/polygon.h"

namespace raycast {
namespace {

constexpr uint32_t N = kNoNormal;

TriangleMesh parse(std::string_view text, int threads = 1, size_t chunk_bytes = 0) {
    ObjLoadOptions options;
    options.threads = threads;
    options.chunk_bytes = chunk_bytes;
    return parse_obj(text, "m.obj", options);
}

// The diagnostics parse_obj throws; an empty list (and a test failure) when it does not throw.
std::vector<Diagnostic> errors_of(std::string_view text, int threads = 1, size_t chunk_bytes = 0) {
    try {
        parse(text, threads, chunk_bytes);
    } catch (const InputError& error) {
        return error.diagnostics();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return {};
}

std::string located(const Diagnostic& d) {
    return d.location.file + ":" + std::to_string(d.location.line) + ":" + std::to_string(d.location.column) + ": " +
           d.message;
}

// "file:line:col: message" for every diagnostic, one a line.
std::string all_located(const std::vector<Diagnostic>& diagnostics) {
    std::string text;
    for (const Diagnostic& d : diagnostics) text += located(d) + "\n";
    return text;
}

// The only error for `text`, as "file:line:col: message".
std::string only_error(std::string_view text) {
    const std::vector<Diagnostic> errors = errors_of(text);
    EXPECT_EQ(errors.size(), 1u) << all_located(errors);
    return errors.empty() ? std::string() : located(errors[0]);
}

std::string describe_difference(const TriangleMesh& a, const TriangleMesh& b) {
    if (a.positions.size() != b.positions.size()) return "positions differ in size";
    for (size_t i = 0; i < a.positions.size(); ++i)
        if (a.positions[i] != b.positions[i]) return "position " + std::to_string(i) + " differs";
    if (a.normals.size() != b.normals.size()) return "normals differ in size";
    for (size_t i = 0; i < a.normals.size(); ++i)
        if (a.normals[i] != b.normals[i]) return "normal " + std::to_string(i) + " differs";
    if (a.indices != b.indices) return "indices differ";
    if (a.normal_indices != b.normal_indices) return "normal_indices differ";
    return "";
}

// ---- accepted input -------------------------------------------------------------------------

TEST(LoadObj, ReadsVerticesAndATriangle) {
    const TriangleMesh mesh = parse("v 0 0 0\nv 1.5 -2 0.25\nv 0 1 3e2\nf 1 2 3\n");
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.positions[0], Vec3f(0, 0, 0));
    EXPECT_EQ(mesh.positions[1], Vec3f(1.5f, -2, 0.25f));
    EXPECT_EQ(mesh.positions[2], Vec3f(0, 1, 300));
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_TRUE(mesh.normals.empty());
    EXPECT_TRUE(mesh.normal_indices.empty());
    EXPECT_FALSE(mesh.has_normals());
}

TEST(LoadObj, AcceptsEveryCornerForm) {
    const std::string head =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\n";
    EXPECT_EQ(parse(head + "f 4 2 3\n").indices, (std::vector<uint32_t>{3, 1, 2}));
    EXPECT_EQ(parse(head + "f 4/1 2/3 3/2\n").indices, (std::vector<uint32_t>{3, 1, 2}));
    const TriangleMesh vn = parse(head + "f 4//3 2//1 3//2\n");
    EXPECT_EQ(vn.indices, (std::vector<uint32_t>{3, 1, 2}));
    EXPECT_EQ(vn.normal_indices, (std::vector<uint32_t>{2, 0, 1}));
    const TriangleMesh vtn = parse(head + "f 4/3/2 2/2/3 3/1/1\n");
    EXPECT_EQ(vtn.indices, (std::vector<uint32_t>{3, 1, 2}));
    EXPECT_EQ(vtn.normal_indices, (std::vector<uint32_t>{1, 2, 0}));
    // A '+' sign is an ordinary integer.
    EXPECT_EQ(parse(head + "f +1 +2 +3\n").indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(LoadObj, NegativeIndicesCountBackFromTheLine) {
    const TriangleMesh mesh = parse(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
        "f -3 -2 -1\n"  // the three vertices so far: 0 1 2
        "v 5 5 5\n"
        "f -1 -4 -2\n"  // now 4 vertices: -1 is vertex 3
        "vn 0 0 1\nvn 0 1 0\n"
        "f -4//-1 -3//-2 -2//-1\n"
        "vt 0 0\n"
        "f 1/-1/2 2/-1/-1 3/1/1\n");
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 3, 0, 2, 0, 1, 2, 0, 1, 2}));
    EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{N, N, N, N, N, N, 1, 0, 1, 1, 1, 0}));
}

TEST(LoadObj, PositiveIndicesMayReferForward) {
    const TriangleMesh mesh = parse("f 1 2 3\nf 3//1 2//1 1//1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n");
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}));
    EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{N, N, N, 0, 0, 0}));
}

// A concave face (an L, as Blender writes n-gons) is cut around its notch, not fanned across it
// (triangulate_polygon, geometry/polygon.h), once every vertex is known: here the face names
// vertices that come after it, in another chunk. Its normal indices go with their corners.
TEST(LoadObj, ConcavePolygonsAreCutAroundTheirNotch) {
    const std::string text = "f 1//1 2//2 3//3 4//4 5//5 6//6\n"
                             "v 1 -1 0\nv 1 0 0\nv 0 0 0\nv 0 1 0\nv -1 1 0\nv -1 -1 0\n"
                             "vn 0 0 1\nvn 0 0 2\nvn 0 0 3\nvn 0 0 4\nvn 0 0 5\nvn 0 0 6\n";
    std::vector<uint32_t> expected(12);
    std::vector<Vec3f> corners{{1, -1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, -1, 0}};
    ASSERT_TRUE(triangulate_polygon(corners.data(), 6, expected.data()));
    for (size_t chunk_bytes : {size_t{0}, size_t{5}, size_t{40}}) {
        ObjLoadOptions options;
        options.threads = 2;
        options.chunk_bytes = chunk_bytes;
        const TriangleMesh mesh = parse_obj(text, "m.obj", options);
        EXPECT_EQ(mesh.indices, expected) << chunk_bytes;
        EXPECT_EQ(mesh.normal_indices, expected) << chunk_bytes;  // normal k sits with vertex k
    }
    // No triangle of the L crosses its missing quarter: none has both corner 0 (1, -1) and 3 (0, 1).
    for (size_t t = 0; t < expected.size(); t += 3) {
        const bool has0 = expected[t] == 0 || expected[t + 1] == 0 || expected[t + 2] == 0;
        const bool has3 = expected[t] == 3 || expected[t + 1] == 3 || expected[t + 2] == 3;
        EXPECT_FALSE(has0 && has3) << t / 3;
    }
}

// A statement OBJ does not define (a typo such as 'f1', or not OBJ at all) is skipped with a
// warning at it: dropping a line silently shifts every relative index after it. The statements
// OBJ defines and raycast does not draw pass in silence. Past 20 warnings, a note counts the rest.
TEST(LoadObj, UnknownStatementsAreSkippedWithAWarning) {
    const auto warnings_of = [](const std::string& text) {
        std::vector<Diagnostic> warnings;
        ObjLoadOptions options;
        options.warnings = &warnings;
        parse_obj(text, "m.obj", options);
        return warnings;
    };
    const std::string known = "o cube\ng side\ns off\nmtllib a.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                              "vp 0.5\nl 1 2\np 3\ncstype bezier\nf 1 2 3\n\n   \n# comment\r\n\r\n";
    EXPECT_TRUE(warnings_of(known).empty());
    const std::vector<Diagnostic> typo = warnings_of("v 0 0 0\nv 1 0 0\nv 0 1 0\n  f1 1 2 3\nV 1 2 3\n");
    ASSERT_EQ(typo.size(), 2u);
    EXPECT_EQ(typo[0].severity, Severity::Warning);
    EXPECT_EQ(located(typo[0]),
              "m.obj:4:3: unknown statement 'f1': the line is skipped (raycast reads v, vn, vt and f, and passes over "
              "the other OBJ statements: o, g, s, usemtl, ...)");
    EXPECT_EQ(typo[0].source_line, "  f1 1 2 3");
    EXPECT_EQ(typo[1].location.line, 5);
    std::string many;
    for (int i = 0; i < 25; ++i) many += "vx 1 2 3\n";
    for (size_t chunk_bytes : {size_t{0}, size_t{10}}) {
        std::vector<Diagnostic> warnings;
        ObjLoadOptions options;
        options.threads = 2;
        options.chunk_bytes = chunk_bytes;
        options.warnings = &warnings;
        parse_obj(many, "m.obj", options);
        ASSERT_EQ(warnings.size(), 21u) << chunk_bytes;
        EXPECT_EQ(warnings[19].location.line, 20);
        EXPECT_EQ(warnings[20].severity, Severity::Note);
        EXPECT_EQ(warnings[20].message, "5 more lines with unknown statements were skipped");
    }
}

// Convex polygons: fans from the first corner, as every OBJ reader cuts them.
TEST(LoadObj, ConvexPolygonsBecomeFansThatKeepTheWinding) {
    const std::string head = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n";
    EXPECT_EQ(parse(head + "f 1 2 3 4\n").indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(parse(head + "f 5 4 3 2 1\n").indices, (std::vector<uint32_t>{4, 3, 2, 4, 2, 1, 4, 1, 0}));
    const TriangleMesh pentagon = parse(head + "vn 0 0 1\nvn 0 0 2\nf 1//1 2//2 3//1 4//2 5//1\n");
    EXPECT_EQ(pentagon.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
    EXPECT_EQ(pentagon.normal_indices, (std::vector<uint32_t>{0, 1, 0, 0, 0, 1, 0, 1, 0}));
}

// A convex face of more corners than ear clipping takes (a disc's cap of 1000) is cut in halves
// (triangulate_polygon), not fanned: its vertices come after it, in other chunks, with normals.
TEST(LoadObj, AConvexFaceOfVeryManyCornersIsCutInHalves) {
    const int n = 1000;
    std::string face = "f", vertices;
    std::vector<Vec3f> corners;
    for (int i = 0; i < n; ++i) {
        const float x = static_cast<float>(std::cos(2 * M_PI * i / n)), y = static_cast<float>(std::sin(2 * M_PI * i / n));
        corners.push_back({x, y, 0});
        face += " " + std::to_string(i + 1) + "//" + std::to_string(i % 2 + 1);
        vertices += string_printf("v %.9g %.9g 0\n", x, y);
    }
    std::vector<uint32_t> expected(3 * (n - 2));
    ASSERT_TRUE(triangulate_polygon(corners.data(), n, expected.data()));
    const std::string text = face + "\n" + vertices + "vn 0 0 1\nvn 0 0 2\n";
    for (size_t chunk_bytes : {size_t{0}, size_t{200}}) {
        ObjLoadOptions options;
        options.threads = 2;
        options.chunk_bytes = chunk_bytes;
        const TriangleMesh mesh = parse_obj(text, "m.obj", options);
        EXPECT_EQ(mesh.indices, expected) << chunk_bytes;
        ASSERT_EQ(mesh.normal_indices.size(), expected.size());
        for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(mesh.normal_indices[i], expected[i] % 2) << i;
    }
}

TEST(LoadObj, AcceptsCommentsBlankLinesTabsAndCrlf) {
    const TriangleMesh mesh = parse(
        "# a comment\r\n"
        "\r\n"
        "   \t\n"
        "\tv\t1 2 3   # trailing comment\r\n"
        "  v 4 5 6#comment right after a number\n"
        "v 7 8 9 \t \r\n"
        "#f 9 9 9\n"
        "f 1 2 3# comment\r\n"
        "  f\t3 2 1  \r\n");
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.positions[0], Vec3f(1, 2, 3));
    EXPECT_EQ(mesh.positions[1], Vec3f(4, 5, 6));
    EXPECT_EQ(mesh.positions[2], Vec3f(7, 8, 9));
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}));
}

TEST(LoadObj, KeepsALastLineWithoutNewline) {
    EXPECT_EQ(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3").indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(parse("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0").positions.back(), Vec3f(0, 1, 0));
    EXPECT_EQ(parse("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r").indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(LoadObj, IgnoresNumbersAfterZAndOtherStatements) {
    const TriangleMesh mesh = parse(
        "mtllib scene.mtl\no thing\ng group\ns 1\nusemtl red\n"
        "v 1 2 3 1.0\n"           // w
        "v 4 5 6 0.5 0.25 1\n"    // vertex colour
        "v 7 8 9\n"
        "vp 0.5 0.5\n"            // not a vertex
        "vertex 1 2 3\n"          // an unknown keyword that starts like one
        "l 1 2\np 3\ncurv 0 1 1 2\nfo 1 2 3\nfoo\n"
        "f 1 2 3\n");
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.positions[0], Vec3f(1, 2, 3));
    EXPECT_EQ(mesh.positions[1], Vec3f(4, 5, 6));
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(LoadObj, ChecksTextureCoordinatesButDoesNotKeepThem) {
    const TriangleMesh mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5\nvt 0.5 0.25\nvt 0.5 0.25 1\nf 1/3 2/2 3/1\n");
    EXPECT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_TRUE(mesh.normal_indices.empty());
    EXPECT_EQ(only_error("v 0 0 0\nvt 0 0\nvt 1 1\nf 1/1 1/2 1/3\n"),
              "m.obj:4:13: texture coordinate index 3 is out of range: the file has 2 texture coordinates");
}

TEST(LoadObj, KeepsNormalsAndNormalIndices) {
    const TriangleMesh mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0.5 -0.5 0.25\nf 1//2 2//1 3//2\n");
    ASSERT_EQ(mesh.normals.size(), 2u);
    EXPECT_EQ(mesh.normals[0], Vec3f(0, 0, 1));
    EXPECT_EQ(mesh.normals[1], Vec3f(0.5f, -0.5f, 0.25f));
    EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{1, 0, 1}));
    EXPECT_TRUE(mesh.has_normals());
}

TEST(LoadObj, FacesWithoutNormalsGetNoNormalBesideFacesWithThem) {
    const TriangleMesh mesh = parse(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\n"
        "f 1 2 3\n"
        "f 2//1 4//1 3//1\n"
        "f 1/1 2/1 3/1 4/1\n"  // needs vt 1
        "vt 0 0\n"
        "f 1//1 2 3/1/1\n");   // corners mix forms: each is taken on its own
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 0, 1, 2, 0, 2, 3, 0, 1, 2}));
    EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{N, N, N, 0, 0, 0, N, N, N, N, N, N, 0, N, 0}));
}

TEST(LoadObj, NormalsThatNoFaceUsesLeaveNormalIndicesEmpty) {
    const TriangleMesh mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1 2/1 3/1\n");
    EXPECT_EQ(mesh.normals.size(), 1u);
    EXPECT_TRUE(mesh.normal_indices.empty());
}

TEST(LoadObj, KeepsPositionsNoFaceUses) {
    const TriangleMesh mesh = parse("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 8 8 8\nf 2 3 4\n");
    ASSERT_EQ(mesh.positions.size(), 5u);
    EXPECT_EQ(mesh.positions[4], Vec3f(8, 8, 8));
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{1, 2, 3}));
}

TEST(LoadObj, EmptyOrCommentOnlyTextGivesAnEmptyMesh) {
    for (std::string_view text : {"", "\n", "# nothing\n", "o empty"}) {
        const TriangleMesh mesh = parse(text);
        EXPECT_TRUE(mesh.positions.empty());
        EXPECT_TRUE(mesh.indices.empty());
    }
}

TEST(LoadObj, SkipsAUtf8ByteOrderMark) {
    const TriangleMesh mesh = parse("\xEF\xBB\xBFv 1 2 3\nv 0 0 0\nv 0 1 0\nf 1 2 3\n");
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.positions[0], Vec3f(1, 2, 3));
    // Columns count from after the mark, which shows as nothing: where an editor puts the 'x', and
    // the caret under the line shown (which leaves the mark out) lands on it.
    const std::vector<Diagnostic> errors = errors_of("\xEF\xBB\xBFv 1 2 x\n");
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(located(errors[0]), "m.obj:1:7: 'x' is not a number");
    EXPECT_EQ(errors[0].source_line, "v 1 2 x");
}

// Files joined together (`copy /b a.obj+b.obj`) carry a mark at the start of a line inside. The
// statement after it used to be dropped as unknown, which shifted every relative index after it.
TEST(LoadObj, SkipsAByteOrderMarkAtTheStartOfAnyLine) {
    const std::string joined = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n\xEF\xBB\xBFv 0 0 1\nv 1 0 1\nv 0 1 1\nf -3 -2 -1\n";
    for (size_t chunk_bytes : {size_t{0}, size_t{1}, size_t{7}}) {
        ObjLoadOptions options;
        options.threads = 2;
        options.chunk_bytes = chunk_bytes;
        const TriangleMesh mesh = parse_obj(joined, "m.obj", options);
        ASSERT_EQ(mesh.positions.size(), 6u) << chunk_bytes;
        EXPECT_EQ(mesh.positions[3], Vec3f(0, 0, 1));
        EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5})) << chunk_bytes;
    }
    EXPECT_EQ(only_error("v 0 0 0\n\xEF\xBB\xBFv 1 2 x\n"), "m.obj:2:7: 'x' is not a number");
}

// Classic Mac OS ended lines with CR alone, and DOS editors put a Ctrl-Z last: both are read as
// the same mesh as LF text, for any chunking, with lines counted as an editor counts them.
TEST(LoadObj, ReadsClassicMacLineBreaksAndADosEndMark) {
    const std::string lf = "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::string mac = lf;
    std::replace(mac.begin(), mac.end(), '\n', '\r');
    const TriangleMesh expected = parse(lf);
    ASSERT_EQ(expected.indices.size(), 6u);
    for (const std::string& text : {mac, lf + "\x1a", mac + "\x1a"}) {
        for (size_t chunk_bytes : {size_t{0}, size_t{1}, size_t{7}}) {
            ObjLoadOptions options;
            options.threads = 2;
            options.chunk_bytes = chunk_bytes;
            const TriangleMesh mesh = parse_obj(text, "m.obj", options);
            EXPECT_EQ(mesh.positions, expected.positions) << chunk_bytes;
            EXPECT_EQ(mesh.indices, expected.indices) << chunk_bytes;
        }
    }
    EXPECT_EQ(only_error("v 0 0 0\rv 1 2 x\r"), "m.obj:2:7: 'x' is not a number");
}

// ---- errors: every message, at file:line:col --------------------------------------------------

TEST(LoadObjErrors, NotANumber) {
    EXPECT_EQ(only_error("v 0 0 0\nv 1 abc 3\n"), "m.obj:2:5: 'abc' is not a number");
    EXPECT_EQ(only_error("vn 1 2 3x\n"), "m.obj:1:8: '3x' is not a number");
    EXPECT_EQ(only_error("vt nan\n"), "m.obj:1:4: 'nan' is not a number");
    EXPECT_EQ(only_error("v 1 2 3 inf\n"), "m.obj:1:9: 'inf' is not a number");  // ignored numbers still count
    EXPECT_EQ(only_error("v 1 2 1e\n"), "m.obj:1:7: '1e' is not a number");
    EXPECT_EQ(only_error("v 1,5 2 3\n"), "m.obj:1:3: '1,5' is not a number");
}

TEST(LoadObjErrors, LongTokensAreCutTo40Characters) {
    const std::string token(45, 'z');
    EXPECT_EQ(only_error("v 1 2 " + token + "\n"), "m.obj:1:7: '" + std::string(40, 'z') + "...' is not a number");
    const std::string exactly_40(40, 'y');
    EXPECT_EQ(only_error("v 1 2 " + exactly_40 + "\n"), "m.obj:1:7: '" + exactly_40 + "' is not a number");
    // The cut never splits a UTF-8 character ("é" is 2 bytes: 39 'a' + 'é' would end at byte 41).
    EXPECT_EQ(only_error("v 1 2 " + std::string(39, 'a') + "\xC3\xA9zz\n"),
              "m.obj:1:7: '" + std::string(39, 'a') + "...' is not a number");
    // Control bytes are shown escaped.
    EXPECT_EQ(only_error(std::string("v 1 2 a\x01", 8) + "\n"), "m.obj:1:7: 'a\\x01' is not a number");
}

TEST(LoadObjErrors, ABinaryFileIsRefusedAtItsFirstBadByteWhereverTheChunksAreCut) {
    // A zip archive appended to a mesh: its header's first NUL; and an ELF executable, whose first
    // byte is the control byte 0x7f (the rule is sceneio/text_check.h's).
    using namespace std::string_literals;  // keeps the NUL bytes
    const std::string zip = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n# binary below\nPK\x03\x04\x14\0\0\0"s;
    const std::string elf = "v 0 0 0\n\x7f" "ELF\x02\x01\x01\n";
    const std::pair<std::string, std::string> cases[] = {
        {zip, "m.obj:6:6: this is not a text file: byte 0x00 (NUL) never appears in text\n"},
        {elf, "m.obj:2:1: this is not a text file: byte 0x7f is a control character at the start of a line\n"},
    };
    for (const auto& [text, expected] : cases) {
        for (size_t chunk_bytes = 1; chunk_bytes <= text.size() + 1; ++chunk_bytes)
            for (int threads : {1, 3})
                EXPECT_EQ(all_located(errors_of(text, threads, chunk_bytes)), expected)
                    << "chunk_bytes " << chunk_bytes << ", threads " << threads;
    }
}

TEST(LoadObjErrors, NumberOutOfRange) {
    EXPECT_EQ(only_error("v 1 1e39 0\n"), "m.obj:1:5: number '1e39' is out of range");
    EXPECT_EQ(only_error("vn -4e38 0 0\n"), "m.obj:1:4: number '-4e38' is out of range");
    // Too small to be a float rounds to zero, as strtof does: no error.
    EXPECT_EQ(parse("v 1e-50 0 0\n").positions[0], Vec3f(0, 0, 0));
}

TEST(LoadObjErrors, TooFewCoordinates) {
    EXPECT_EQ(only_error("v 1 2 3\n  v 1 2\n"), "m.obj:2:3: a vertex needs 3 coordinates (x y z)");
    EXPECT_EQ(only_error("v # 1 2 3\n"), "m.obj:1:1: a vertex needs 3 coordinates (x y z)");
    EXPECT_EQ(only_error("vn 1 2\n"), "m.obj:1:1: a normal needs 3 coordinates (x y z)");
    EXPECT_EQ(only_error("\tvt\n"), "m.obj:1:2: a texture coordinate needs at least 1 number");
}

// "1.#IND" is how old Microsoft C libraries printed a NaN. The '#' would start a comment and the
// number be read as 1 (or the coordinates after it go missing): it is refused as not a number.
TEST(LoadObjErrors, MicrosoftNanAndInfinityAreNotNumbers) {
    const std::string why = " is not a number: old Microsoft C libraries wrote NaN and infinity as '1.#IND' and "
                            "'1.#INF' (the '#' is not a comment here), and no mesh may hold them";
    EXPECT_EQ(only_error("vn -1.#IND 0 1\n"), "m.obj:1:4: '-1.#IND'" + why);
    EXPECT_EQ(only_error("v 0 0 1.#INF\n"), "m.obj:1:7: '1.#INF'" + why);
    EXPECT_EQ(only_error("v 0 0 0\nv 0 -1.#QNAN 0\n"), "m.obj:2:5: '-1.#QNAN'" + why);
    EXPECT_EQ(only_error("vt 1.#SNAN\n"), "m.obj:1:4: '1.#SNAN'" + why);
    EXPECT_EQ(only_error("v 0 0 1.#IND00 \r\n"), "m.obj:1:7: '1.#IND00'" + why);
    // Other comments glued to a number are comments.
    EXPECT_EQ(parse("v 1 2 3#c\nv 1 2 4#INDEX\nv 1 2 5 #IND\n").positions,
              (std::vector<Vec3f>{Vec3f(1, 2, 3), Vec3f(1, 2, 4), Vec3f(1, 2, 5)}));
}

// The OBJ specification's line continuation, a '\\' last on a line, is not read: the error says so.
TEST(LoadObjErrors, ALineContinuationIsNamed) {
    const std::string why = ": a '\\' at the end of a line, which OBJ reads as \"the statement goes on below\", is not "
                            "read here: join the two lines";
    EXPECT_EQ(only_error("v 1 2 \\\n"), "m.obj:1:7: '\\' is not a number" + why);
    EXPECT_EQ(only_error("v 1 2 \\ \r\n"), "m.obj:1:7: '\\' is not a number" + why);
    const std::vector<Diagnostic> errors = errors_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n3\n");
    ASSERT_FALSE(errors.empty());
    EXPECT_EQ(located(errors[0]), "m.obj:4:7: malformed face vertex '\\'" + why);
    // A '\\' inside a line is only not a number.
    EXPECT_EQ(only_error("v 1 \\ 2 3\n"), "m.obj:1:5: '\\' is not a number");
}

TEST(LoadObjErrors, FaceWithTooFewVertices) {
    EXPECT_EQ(only_error("v 0 0 0\nv 1 0 0\nf 1 2\n"), "m.obj:3:1: a face needs at least 3 vertices, this one has 2");
    EXPECT_EQ(only_error(" f  # empty\n"), "m.obj:1:2: a face needs at least 3 vertices, this one has 0");
}

TEST(LoadObjErrors, IndexZero) {
    EXPECT_EQ(only_error("v 0 0 0\nv 1 0 0\nf 1 0 2\n"), "m.obj:3:5: index 0 is invalid: OBJ indices start at 1");
    EXPECT_EQ(only_error("v 0 0 0\nvn 0 0 1\nf 1//1 1//0 1//1\n"),
              "m.obj:3:11: index 0 is invalid: OBJ indices start at 1");
    EXPECT_EQ(only_error("v 0 0 0\nvt 0\nf 1/-0 1/1 1/1\n"), "m.obj:3:5: index 0 is invalid: OBJ indices start at 1");
}

TEST(LoadObjErrors, PositiveIndexOutOfRange) {
    const std::string cube = "v 0 0 0\nv 0 0 1\nv 0 1 0\nv 0 1 1\nv 1 0 0\nv 1 0 1\nv 1 1 0\nv 1 1 1\n";
    EXPECT_EQ(only_error(cube + "f 1 9 2\n"), "m.obj:9:5: vertex index 9 is out of range: the file has 8 vertices");
    EXPECT_EQ(only_error("v 0 0 0\nf 1 1 2\n"), "m.obj:2:7: vertex index 2 is out of range: the file has 1 vertex");
    EXPECT_EQ(all_located(errors_of("f 1 2 1\n")),
              "m.obj:1:3: vertex index 1 is out of range: the file has 0 vertices\n"
              "m.obj:1:5: vertex index 2 is out of range: the file has 0 vertices\n"
              "m.obj:1:7: vertex index 1 is out of range: the file has 0 vertices\n");
    EXPECT_EQ(only_error("v 0 0 0\nvn 0 0 1\nvn 1 0 0\nf 1//1 1//3 1//2\n"),
              "m.obj:4:11: normal index 3 is out of range: the file has 2 normals");
    EXPECT_EQ(only_error("v 0 0 0\nvt 0\nvn 0 0 1\nf 1//1 1//1 1/1/2\n"),
              "m.obj:4:17: normal index 2 is out of range: the file has 1 normal");
    EXPECT_EQ(only_error("v 0 0 0\nvt 0 0\nf 1/1 1/1 1/2\n"),
              "m.obj:3:13: texture coordinate index 2 is out of range: the file has 1 texture coordinate");
    // Too large even for parse_int: shown as written.
    EXPECT_EQ(only_error("v 0 0 0\nf 1 1 99999999999999999999\n"),
              "m.obj:2:7: vertex index 99999999999999999999 is out of range: the file has 1 vertex");
}

TEST(LoadObjErrors, NegativeIndexOutOfRange) {
    EXPECT_EQ(only_error("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"),
              "m.obj:3:9: vertex index -3 is out of range: 2 vertices are defined before this line");
    EXPECT_EQ(only_error("v 0 0 0\nf -1 -2 -1\nv 1 0 0\n"),
              "m.obj:2:6: vertex index -2 is out of range: 1 vertex is defined before this line");
    EXPECT_EQ(only_error("f -1 1 1\nv 0 0 0\n"),
              "m.obj:1:3: vertex index -1 is out of range: 0 vertices are defined before this line");
    EXPECT_EQ(only_error("v 0 0 0\nf 1//-1 1 1\nvn 0 0 1\n"),
              "m.obj:2:6: normal index -1 is out of range: 0 normals are defined before this line");
    EXPECT_EQ(only_error("v 0 0 0\nvt 0\nf 1/-2 1 1\nvt 1\n"),
              "m.obj:3:5: texture coordinate index -2 is out of range: "
              "1 texture coordinate is defined before this line");
    EXPECT_EQ(only_error("v 0 0 0\nf 1 1 -99999999999999999999\n"),
              "m.obj:2:7: vertex index -99999999999999999999 is out of range: 1 vertex is defined before this line");
}

TEST(LoadObjErrors, MalformedFaceVertex) {
    const std::string head = "v 0 0 0\nvt 0 0\nvn 0 0 1\n";
    for (const char* corner : {"1/x/3", "1/", "1//", "1/1/", "/1", "//1", "1/1/1/1", "1.5", "a", "1-2", "-", "1//1x"}) {
        EXPECT_EQ(only_error(head + "f 1 1 " + corner + "\n"),
                  std::string("m.obj:4:7: malformed face vertex '") + corner + "'");
    }
}

TEST(LoadObjErrors, ErrorsOfOneLineComeInColumnOrder) {
    const std::vector<Diagnostic> errors = errors_of("v 0 0 0\nv x\nf 0 7//1\n");
    EXPECT_EQ(all_located(errors),
              "m.obj:2:1: a vertex needs 3 coordinates (x y z)\n"
              "m.obj:2:3: 'x' is not a number\n"
              "m.obj:3:1: a face needs at least 3 vertices, this one has 2\n"
              "m.obj:3:3: index 0 is invalid: OBJ indices start at 1\n"
              "m.obj:3:5: vertex index 7 is out of range: the file has 2 vertices\n"
              "m.obj:3:8: normal index 1 is out of range: the file has 0 normals\n");
}

TEST(LoadObjErrors, CarriesTheSourceLineForTheCaret) {
    const std::vector<Diagnostic> errors = errors_of("v 0 0 0\r\n\tv 1 bad 2\r\nv 0 1 0\r\n");
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(errors[0].severity, Severity::Error);
    EXPECT_EQ(errors[0].source_line, "\tv 1 bad 2");
    EXPECT_EQ(format_diagnostic(errors[0]),
              "m.obj:2:6: error: 'bad' is not a number\n"
              "  \tv 1 bad 2\n"
              "  \t    ^\n");
    // On a last line without a newline too.
    const std::vector<Diagnostic> last = errors_of("v 0 0 0\nf 1 1 2");
    ASSERT_EQ(last.size(), 1u);
    EXPECT_EQ(last[0].source_line, "f 1 1 2");
    // Not a line longer than 300 bytes (a face of many corners), as the scene parser's rule is:
    // each error printed it whole.
    std::string long_face = "v 0 0 0\nf";
    for (int i = 0; i < 200; ++i) long_face += " 1";
    const std::vector<Diagnostic> on_long = errors_of(long_face + " 9\n");
    ASSERT_EQ(on_long.size(), 1u);
    EXPECT_EQ(on_long[0].location.column, 403);
    EXPECT_EQ(on_long[0].source_line, "");
}

TEST(LoadObjErrors, StopsAfter20Errors) {
    std::string text = "v 0 0 0\n";
    for (int i = 0; i < 30; ++i) text += "f 1 1 " + std::to_string(100 + i) + "\n";
    for (int threads : {1, 4}) {
        for (size_t chunk_bytes : {size_t{0}, size_t{10}, size_t{64}}) {
            const std::vector<Diagnostic> errors = errors_of(text, threads, chunk_bytes);
            ASSERT_EQ(errors.size(), 20u);
            EXPECT_EQ(located(errors.front()), "m.obj:2:7: vertex index 100 is out of range: the file has 1 vertex");
            EXPECT_EQ(located(errors.back()), "m.obj:21:7: vertex index 119 is out of range: the file has 1 vertex");
        }
    }
    // Several errors on the last line collected keep column order and the cut.
    std::string crowded = "v 0 0 0\n";
    for (int i = 0; i < 19; ++i) crowded += "v x 0 0\n";
    crowded += "v a b c\n";
    const std::vector<Diagnostic> errors = errors_of(crowded);
    ASSERT_EQ(errors.size(), 20u);
    EXPECT_EQ(located(errors.back()), "m.obj:21:3: 'a' is not a number");
}

// ---- files -----------------------------------------------------------------------------------

std::string write_temp_file(const std::string& name, std::string_view content) {
    const std::string path = ::testing::TempDir() + "load_obj_test_" + name;
    std::FILE* file = std::fopen(path.c_str(), "wb");
    EXPECT_NE(file, nullptr) << path;
    if (file) {
        std::fwrite(content.data(), 1, content.size(), file);
        std::fclose(file);
    }
    return path;
}

TEST(LoadObjFile, LoadsAFile) {
    const std::string path = write_temp_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4");
    ObjLoadOptions options;
    FileVersion opened;
    options.opened = &opened;
    const TriangleMesh mesh = load_obj_file(path, options);
    EXPECT_EQ(mesh.positions.size(), 4u);
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    // The version of the file it read, for the viewer to compare with the file later.
    EXPECT_EQ(opened.size, 41);
    EXPECT_EQ(opened, current_version(path));
    std::remove(path.c_str());
}

TEST(LoadObjFile, LocatesErrorsInTheFile) {
    const std::string path = write_temp_file("bad.obj", "v 0 0 0\nf 1 1 2\n");
    try {
        load_obj_file(path, ObjLoadOptions{2});
        ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
        ASSERT_EQ(error.diagnostics().size(), 1u);
        EXPECT_EQ(located(error.diagnostics()[0]),
                  path + ":2:7: vertex index 2 is out of range: the file has 1 vertex");
    }
    std::remove(path.c_str());
}

// The single diagnostic of a file-level error, as "file:line:col: message".
std::string file_error(const std::string& path) {
    try {
        load_obj_file(path);
    } catch (const InputError& error) {
        EXPECT_EQ(error.diagnostics().size(), 1u);
        return located(error.diagnostics()[0]);
    }
    return "no error";
}

TEST(LoadObjFile, ReportsAMissingFile) {
    const std::string path = ::testing::TempDir() + "load_obj_test_no_such_file.obj";
    EXPECT_EQ(file_error(path), path + ":0:0: cannot open OBJ file: No such file or directory");
}

TEST(LoadObjFile, ReportsADirectory) {
    const std::string path = ::testing::TempDir();
    EXPECT_EQ(file_error(path), path + ":0:0: cannot open OBJ file: it is a directory");
}

// ---- threads and chunks ------------------------------------------------------------------------

// A text with every feature, for cutting into chunks of every size.
const char* const kEveryFeature =
    "# header\r\n"
    "v 0 0 0\r\n"
    "v 1 0 0 1\n"
    "\tv 1 1 0\n"
    "vt 0 0\n"
    "vn 0 0 1\n"
    "f 1 2 3\n"
    "v 0 1 0 # fourth\n"
    "f -4/-1/-1 -3/1/1 -2//1 -1\n"
    "\n"
    "o name\n"
    "f 1/1 2/1 3/1 4/1 5/1\n"
    "v 2 2 2";

TEST(LoadObjChunks, EveryChunkSizeGivesTheSameMesh) {
    const std::string_view text = kEveryFeature;
    const TriangleMesh reference = parse(text);
    ASSERT_EQ(reference.positions.size(), 5u);
    EXPECT_EQ(reference.positions[4], Vec3f(2, 2, 2));
    EXPECT_EQ(reference.indices, (std::vector<uint32_t>{0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3, 0, 3, 4}));
    EXPECT_EQ(reference.normal_indices, (std::vector<uint32_t>{N, N, N, 0, 0, 0, 0, 0, N, N, N, N, N, N, N, N, N, N}));
    for (size_t chunk_bytes = 1; chunk_bytes <= text.size() + 1; ++chunk_bytes) {
        for (int threads : {1, 3}) {
            EXPECT_EQ(describe_difference(reference, parse(text, threads, chunk_bytes)), "")
                << "chunk_bytes " << chunk_bytes << ", threads " << threads;
        }
    }
}

TEST(LoadObjChunks, EveryChunkSizeGivesTheSameErrors) {
    const std::string text = std::string(kEveryFeature) + "\nf 1 2 -6\nvn x 0 0\nf 1//3 2 3\nf 9 9\n";
    const std::string expected =
        "m.obj:14:7: vertex index -6 is out of range: 5 vertices are defined before this line\n"
        "m.obj:15:4: 'x' is not a number\n"
        "m.obj:16:6: normal index 3 is out of range: the file has 2 normals\n"
        "m.obj:17:1: a face needs at least 3 vertices, this one has 2\n"
        "m.obj:17:3: vertex index 9 is out of range: the file has 5 vertices\n"
        "m.obj:17:5: vertex index 9 is out of range: the file has 5 vertices\n";
    EXPECT_EQ(all_located(errors_of(text)), expected);
    for (size_t chunk_bytes = 1; chunk_bytes <= text.size() + 1; ++chunk_bytes) {
        for (int threads : {1, 3}) {
            EXPECT_EQ(all_located(errors_of(text, threads, chunk_bytes)), expected)
                << "chunk_bytes " << chunk_bytes << ", threads " << threads;
        }
    }
}

// A grid of side x side vertices written a row at a time, each row followed by the faces that join
// it to the row before in one of three styles (positive quads; negative-index triangles with
// normals; tab-separated v/t/n quads with CRLF), with the mesh it must give computed alongside.
struct GeneratedObj {
    std::string text;
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    std::vector<uint32_t> normal_indices;
    int lines = 0;  // lines written so far
};

void add_line(GeneratedObj& obj, const std::string& line) {
    obj.text += line;
    ++obj.lines;
}

GeneratedObj make_grid_obj(int side, int error_row = -1) {
    GeneratedObj obj;
    obj.text.reserve(static_cast<size_t>(side) * side * 70);
    add_line(obj, "# generated grid\n");
    char line[128];
    for (int row = 0; row < side; ++row) {
        for (int i = 0; i < side; ++i) {
            // Multiples of 1/8 and 1/16 print exactly with %.4f, so the floats are known exactly.
            const Vec3f p(static_cast<float>(i) * 0.125f, static_cast<float>(row) * 0.125f,
                          static_cast<float>((i * 7 + row * 3) % 16) * 0.0625f);
            std::snprintf(line, sizeof line, "v %.4f %.4f %.4f\n", double(p.x), double(p.y), double(p.z));
            add_line(obj, line);
            add_line(obj, "vn 0 0 1\n");
            add_line(obj, "vt 0.5 0.5\n");
            obj.positions.push_back(p);
        }
        if (row == 0) continue;
        if (row == error_row) {
            // Late errors: a negative index reaching before the file start, forward ones past its end.
            const long long defined = static_cast<long long>(row + 1) * side;
            std::snprintf(line, sizeof line, "f 1 -%lld 2\n", defined + 1);
            add_line(obj, line);
            const long long total = static_cast<long long>(side) * side;
            std::snprintf(line, sizeof line, "f 1 2 %lld/%lld\n", total + 2, total + 1);
            add_line(obj, line);
        }
        const int defined = (row + 1) * side;  // vertices (and normals) defined so far
        for (int i = 0; i + 1 < side; ++i) {
            const int a = (row - 1) * side + i + 1;  // 1-based corners of the quad, counter-clockwise
            const int b = a + 1;
            const int c = row * side + i + 2;
            const int d = c - 1;
            const uint32_t q[4] = {uint32_t(a - 1), uint32_t(b - 1), uint32_t(c - 1), uint32_t(d - 1)};
            const uint32_t fan[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
            obj.indices.insert(obj.indices.end(), fan, fan + 6);
            if (row % 3 == 0) {
                std::snprintf(line, sizeof line, "f %d %d %d %d\n", a, b, c, d);
                add_line(obj, line);
                obj.normal_indices.insert(obj.normal_indices.end(), 6, kNoNormal);
            } else if (row % 3 == 1) {
                const int na = a - defined - 1, nb = b - defined - 1, nc = c - defined - 1, nd = d - defined - 1;
                std::snprintf(line, sizeof line, "f %d//%d %d//%d %d//%d\n", na, na, nb, nb, nc, nc);
                add_line(obj, line);
                std::snprintf(line, sizeof line, "f %d//%d %d//%d %d//%d\n", na, na, nc, nc, nd, nd);
                add_line(obj, line);
                obj.normal_indices.insert(obj.normal_indices.end(), fan, fan + 6);
            } else {
                std::snprintf(line, sizeof line, "f\t%d/%d/%d %d/%d/%d\t%d/%d/%d %d/%d/%d # quad\r\n", a, a, a, b, b,
                              b, c, c, c, d, d, d);
                add_line(obj, line);
                obj.normal_indices.insert(obj.normal_indices.end(), fan, fan + 6);
            }
        }
    }
    return obj;
}

TEST(LoadObjChunks, ThreadsGiveTheSameLargeMesh) {
    const GeneratedObj obj = make_grid_obj(300);
    ASSERT_GT(obj.text.size(), size_t{8} << 20);  // several chunks per thread
    const TriangleMesh one = parse(obj.text, 1);
    EXPECT_EQ(one.positions.size(), 300u * 300u);
    EXPECT_EQ(one.triangle_count(), 2u * 299u * 299u);
    EXPECT_TRUE(one.positions == obj.positions);
    EXPECT_TRUE(one.indices == obj.indices);
    EXPECT_TRUE(one.normal_indices == obj.normal_indices);
    EXPECT_EQ(one.normals.size(), 300u * 300u);
    for (int threads : {2, 4}) {
        EXPECT_EQ(describe_difference(one, parse(obj.text, threads)), "") << threads << " threads";
    }
    EXPECT_EQ(describe_difference(one, parse(obj.text, 4, 1000)), "");
    // Thread counts below 1 mean 1.
    EXPECT_EQ(describe_difference(one, parse(obj.text, 0)), "");
    EXPECT_EQ(describe_difference(one, parse(obj.text, -3)), "");
}

// A file of 1 MiB or more is read by every thread at once, each a range of it
// (read_ranges_at_once): the mesh is the text's, whatever the number of ranges.
TEST(LoadObjFile, ALargeFileReadByEveryThreadAtOnceGivesTheSameMesh) {
    const GeneratedObj obj = make_grid_obj(300);
    ASSERT_GT(obj.text.size(), size_t{8} << 20);
    const std::string path = write_temp_file("grid.obj", obj.text);
    const TriangleMesh reference = parse(obj.text, 1);
    for (int threads : {1, 2, 3, 7}) {
        ObjLoadOptions options;
        options.threads = threads;
        EXPECT_EQ(describe_difference(reference, load_obj_file(path, options)), "") << threads << " threads";
    }
    std::remove(path.c_str());
}

TEST(LoadObjChunks, ThreadsGiveTheSameLateErrors) {
    GeneratedObj obj = make_grid_obj(300, 250);
    add_line(obj, "v 1 2\n");  // the very last line, a vertex short of a number
    // The error lines follow row 250's vertices: the header, 251 rows of v/vn/vt lines, then the
    // faces of rows 1..249, which are 83 rows of each style (598, 299 and 299 lines).
    const int line = 1 + 251 * 300 * 3 + 83 * (598 + 299 + 299) + 1;
    ASSERT_EQ(line, 325170);
    ASSERT_EQ(obj.lines, 1 + 300 * 300 * 3 + 100 * (598 + 299 + 299) - 299 + 2 + 1);  // no row 300
    const std::string expected =
        "m.obj:325170:5: vertex index -75301 is out of range: 75300 vertices are defined before this line\n"
        "m.obj:325171:7: vertex index 90002 is out of range: the file has 90001 vertices\n"
        "m.obj:325171:13: texture coordinate index 90001 is out of range: the file has 90000 texture coordinates\n"
        "m.obj:" + std::to_string(obj.lines) + ":1: a vertex needs 3 coordinates (x y z)\n";
    EXPECT_EQ(all_located(errors_of(obj.text, 1)), expected);
    for (int threads : {2, 4}) EXPECT_EQ(all_located(errors_of(obj.text, threads)), expected) << threads << " threads";
    EXPECT_EQ(all_located(errors_of(obj.text, 4, 4096)), expected);
}

}  // namespace
}  // namespace raycast
