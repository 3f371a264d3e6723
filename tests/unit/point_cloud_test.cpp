// Point clouds and line files load (PLY of vertices alone in ASCII and both binary byte orders, XYZ,
// PTS, OBJ `v` lines alone, OBJ `l` lines, glTF's point and line modes) into Mesh::points and
// Mesh::lines with their colours and normals; bad ones give an error naming the file and the problem
// (a header claiming 10^8 vertices in a small file, a line that is not numbers), NaN points are
// dropped with a warning; and render_scene draws them.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace fs = std::filesystem;

struct Vertex {
    float x, y, z, nx, ny, nz;
    unsigned char r, g, b;
};
const Vertex k_vertices[] = {{0, 0, 0, 0, 0, 1, 255, 0, 0}, {1, 0, 0, 0, 1, 0, 0, 255, 0},
                             {0, 1, 0, 1, 0, 0, 0, 0, 255}, {1, 1, 1, 0, 0, 2, 10, 20, 30}};

std::string ply_header(const char* format, int count) {
    return std::string("ply\nformat ") + format + " 1.0\ncomment a cloud\nelement vertex " + std::to_string(count) +
           "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
           "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 0\n"
           "property list uchar int vertex_indices\nend_header\n";
}

std::string ascii_ply() {
    std::string s = ply_header("ascii", 4);
    for (const Vertex& v : k_vertices)
        s += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + " " + std::to_string(v.nx) + " " +
             std::to_string(v.ny) + " " + std::to_string(v.nz) + " " + std::to_string(v.r) + " " + std::to_string(v.g) + " " +
             std::to_string(v.b) + "\n";
    return s;
}

std::string binary_ply(bool big) {
    std::string s = ply_header(big ? "binary_big_endian" : "binary_little_endian", 4);
    auto put = [&](const void* p, std::size_t n) {
        std::string bytes(static_cast<const char*>(p), n);
        if (big) std::reverse(bytes.begin(), bytes.end());
        s += bytes;
    };
    for (const Vertex& v : k_vertices) {
        for (float f : {v.x, v.y, v.z, v.nx, v.ny, v.nz}) put(&f, 4);
        for (unsigned char c : {v.r, v.g, v.b}) put(&c, 1);
    }
    return s;
}

void expect_the_cloud(const Result<LoadedModel>& r) {
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects.size(), 1u);
    const Mesh& m = r->scene.objects[0].mesh;
    EXPECT_TRUE(m.indices.empty());
    EXPECT_TRUE(m.lines.empty());
    ASSERT_EQ(m.points.size(), 4u);
    ASSERT_EQ(m.positions.size(), 4u);
    ASSERT_EQ(m.colours.size(), 4u);
    ASSERT_EQ(m.normals.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        const Vertex& v = k_vertices[i];
        EXPECT_EQ(m.points[i], i);
        EXPECT_EQ(m.positions[i].x, v.x);
        EXPECT_EQ(m.positions[i].z, v.z);
        EXPECT_FLOAT_EQ(m.colours[i].x, v.r / 255.0f);
        EXPECT_FLOAT_EQ(m.colours[i].y, v.g / 255.0f);
        EXPECT_FLOAT_EQ(m.colours[i].w, 1.0f);
        EXPECT_FLOAT_EQ(length(m.normals[i]), 1.0f);
    }
    EXPECT_FLOAT_EQ(m.normals[3].z, 1.0f);
}

TEST(PointCloud, PlyOfVerticesAloneInEveryEncoding) {
    const fs::path dir = facet_test::test_temp_dir("point_cloud");
    expect_the_cloud(load_model(facet_test::write_file(dir / "a.ply", ascii_ply())));
    expect_the_cloud(load_model(facet_test::write_file(dir / "le.ply", binary_ply(false))));
    expect_the_cloud(load_model(facet_test::write_file(dir / "be.ply", binary_ply(true))));
    // Without the (empty) face element, and with CRLF line ends.
    std::string crlf;
    for (char c : "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
                  "end_header\n0 0 0\n1 2 3\n")
        if (c) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const Result<LoadedModel> r = load_model(facet_test::write_file(dir / "crlf.ply", crlf));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->scene.objects[0].mesh.points.size(), 2u);
    EXPECT_EQ(r->scene.objects[0].mesh.positions[1].z, 3.0f);
    EXPECT_TRUE(r->scene.objects[0].mesh.colours.empty());
}

TEST(PointCloud, BadCloudsAreClearErrors) {
    const fs::path dir = facet_test::test_temp_dir("point_cloud");
    // 10^8 vertices claimed by a file of a few hundred bytes: refused before anything is allocated.
    std::string huge = binary_ply(false);
    huge.replace(huge.find("vertex 4"), 8, "vertex 100000000");
    Result<LoadedModel> r = load_model(facet_test::write_file(dir / "huge.ply", huge));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("huge.ply"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("100000000"), std::string::npos) << r.error().message;
    // Truncated ASCII: a value missing.
    std::string cut = ascii_ply();
    cut.resize(cut.size() - 6);
    r = load_model(facet_test::write_file(dir / "cut.ply", cut));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("cut.ply"), std::string::npos) << r.error().message;
    // More points than --max-triangles.
    LoadOptions few;
    few.max_triangles = 3;
    r = load_model(facet_test::write_file(dir / "four.ply", ascii_ply()), few);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::limit_exceeded);
    r = load_model(facet_test::write_file(dir / "bad.xyz", "0 0 0\n1 2 3\n1 two 3\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("line 3"), std::string::npos) << r.error().message;
    r = load_model(facet_test::write_file(dir / "ragged.xyz", "0 0 0\n1 2 3 4 5 6\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("line 2"), std::string::npos) << r.error().message;
    r = load_model(facet_test::write_file(dir / "nan.xyz", "nan 0 0\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("no valid points"), std::string::npos) << r.error().message;
}

TEST(PointCloud, NonFinitePointsAreDroppedWithAWarning) {
    const fs::path dir = facet_test::test_temp_dir("point_cloud");
    const Result<LoadedModel> r = load_model(facet_test::write_file(dir / "some.xyz", "0 0 0\nnan 1 1\n1 inf 1\n2 2 2\n"));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->scene.objects[0].mesh.points.size(), 2u);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_NE(r->warnings[0].find("dropped 2 points"), std::string::npos) << r->warnings[0];
}

TEST(PointCloud, XyzPtsAndObjVertices) {
    const fs::path dir = facet_test::test_temp_dir("point_cloud");
    Result<LoadedModel> r = load_model(facet_test::write_file(dir / "n.xyz", "# x y z nx ny nz\n0 0 0 0 0 3\n\n1 1 1 0 1 0\n"));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->scene.objects[0].mesh.points.size(), 2u);
    ASSERT_EQ(r->scene.objects[0].mesh.normals.size(), 2u);
    EXPECT_EQ(r->scene.objects[0].mesh.normals[0].z, 1.0f);
    r = load_model(facet_test::write_file(dir / "c.pts", "3\n0 0 0 -200 255 0 0\n1 0 0 5 0 255 0\n0 1 0 5 0 0 51\n"));
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects[0].mesh.colours.size(), 3u);
    EXPECT_EQ(r->scene.objects[0].mesh.colours[0].x, 1.0f);
    EXPECT_FLOAT_EQ(r->scene.objects[0].mesh.colours[2].z, 0.2f);
    r = load_model(facet_test::write_file(dir / "v.obj", "# vertices\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nvn 0 0 1\nv 0 1 0 0 0 1\n"));
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects[0].mesh.points.size(), 3u);
    EXPECT_EQ(r->scene.objects[0].mesh.colours[1].y, 1.0f);
    // OBJ `l` lines go through assimp: a polyline of 3 segments sharing their ends.
    r = load_model(facet_test::write_file(dir / "l.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nl 1 2 3 4\n"));
    ASSERT_TRUE(r) << r.error().message;
    const Mesh& m = r->scene.objects[0].mesh;
    ASSERT_EQ(m.lines.size(), 6u);
    EXPECT_EQ(m.lines[1], m.lines[2]);
    EXPECT_EQ(m.lines[3], m.lines[4]);
    EXPECT_TRUE(is_supported_model_file("scan.XYZ"));
    EXPECT_TRUE(is_supported_model_file("scan.pts"));
}

// The glTF Asset Generator's primitive modes: points (00), lines, line loop and line strip (01-03),
// triangles (04-06). Each loads with its kind and renders some pixels.
TEST(PointCloud, GltfPrimitiveModesLoadAndRender) {
    const fs::path dir = facet_test::k_assimp_models / "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode";
    if (!fs::exists(dir)) GTEST_SKIP() << facet_test::assimp_models_missing();
    Renderer renderer({.threads = 2});
    for (int mode = 0; mode <= 6; ++mode) {
        const std::string path = (dir / ("Mesh_PrimitiveMode_0" + std::to_string(mode) + ".gltf")).string();
        const Result<LoadedModel> r = load_model(path);
        ASSERT_TRUE(r) << r.error().message;
        std::size_t points = 0, lines = 0, triangles = 0;
        for (const SceneObject& o : r->scene.objects)
            points += o.mesh.points.size(), lines += o.mesh.lines.size() / 2, triangles += o.mesh.triangle_count();
        const std::size_t expected_points = mode == 0 ? points : 0, expected_lines = mode >= 1 && mode <= 3 ? lines : 0;
        EXPECT_EQ(points, expected_points) << path;
        EXPECT_EQ(lines, expected_lines) << path;
        EXPECT_GT(mode == 0 ? points : mode <= 3 ? lines : triangles, mode == 0 ? 100u : mode <= 3 ? 2u : 1u) << path;
        Framebuffer fb(96, 96);
        const Camera camera = frame_scene(r->scene, 0, 0, radians(45.0f), 1.0f);
        RenderSettings settings;
        settings.background = {0, 0, 0, 1};
        const DrawStats stats = render_scene(renderer, fb, r->scene, camera, settings);
        int lit = 0;
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 96; ++x) lit += fb.colour(x, y).r + fb.colour(x, y).g + fb.colour(x, y).b > 0;
        EXPECT_GT(lit, mode == 0 ? 100 : 60) << path;
        EXPECT_EQ(stats.points_in, points) << path;
        EXPECT_EQ(stats.segments_in, lines) << path;
    }
}

}  // namespace
