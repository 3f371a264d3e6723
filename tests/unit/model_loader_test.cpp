// Model loading (load_model) and creased normals. Three kinds of test:
//  - small files written here with known contents (OBJ, STL, PLY, OFF, glTF/GLB): counts,
//    positions, node transforms, instances, up axis, vertex colours, uv orientation, materials,
//    textures found leniently or warned about, crease-angle normals;
//  - bad input: missing, directory, unreadable, unknown, empty, truncated, garbage, bogus header
//    counts (fast, without allocating what they claim), bad indices, non-finite coordinates, no
//    triangles, limits;
//  - real files from Debian's assimp-testmodels and libcgal-demo (scripts/setup installs them;
//    the tests skip, saying so, when they are absent), checked against what the test reads from
//    the files itself.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "facet/io.hpp"
#include "facet/math/transform.hpp"
#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "support/stl_files.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::read_file;
using facet_test::write_file;
using facet_test::ascii_stl;
using facet_test::binary_stl;
using facet_test::triangles_of;
using facet_test::base64;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();
using facet_test::cgal_meshes;
using facet_test::k_assimp_models;

// ---------------------------------------------------------------------------------------------
// Helpers: files

fs::path temp_dir() { return facet_test::test_temp_dir("facet_model_test"); }

template <class T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian host, as the formats want
    out.append(bytes, sizeof(T));
}

// A 2x2 texture: top row red, green; bottom row blue, white.
const Rgba8 k_red{255, 0, 0, 255}, k_green{0, 255, 0, 255}, k_blue{0, 0, 255, 255}, k_white{255, 255, 255, 255};
std::string write_test_png(const fs::path& path) {
    const Image img{2, 2, {k_red, k_green, k_blue, k_white}};
    EXPECT_TRUE(write_png(path.string(), img).ok());
    return path.string();
}

// One triangle (0,0,0) (1,0,0) (0,1,0) with uvs (0,0) (1,0) (0,1), in a glTF buffer: positions
// at 0, uvs at 36, uint16 indices at 60 (68 bytes with padding).
std::string triangle_buffer(std::uint16_t third_index = 2) {
    std::string b;
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, v);
    for (float v : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) put(b, v);
    for (std::uint16_t i : {std::uint16_t{0}, std::uint16_t{1}, third_index}) put(b, i);
    put(b, std::uint16_t{0});
    return b;
}

// A glTF 2.0 document: root node translated by (1, 2, 3) with two children that both place the
// triangle mesh: node 1 by a column-major matrix (+90 degrees about Z, then +5 in x), node 2
// scaled by 2. `buffer_uri` empty means the GLB's binary chunk. With a texture, the material's
// base colour texture is `image_uri` with clamp (S) and mirrored repeat (T) wrapping.
std::string gltf_json(const std::string& buffer_uri, const std::string& image_uri = "") {
    const bool textured = !image_uri.empty();
    std::ostringstream j;
    j << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"translation":[1,2,3],"children":[1,2]},
         {"matrix":[0,1,0,0, -1,0,0,0, 0,0,1,0, 5,0,0,1],"mesh":0},
         {"scale":[2,2,2],"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.25,1.0,0.75])";
    if (textured) j << R"(,"baseColorTexture":{"index":0})";
    j << R"(},"alphaMode":"MASK","alphaCutoff":0.3,"doubleSided":true}],)";
    if (textured)
        j << R"("textures":[{"sampler":0,"source":0}],"samplers":[{"wrapS":33071,"wrapT":33648}],"images":[{"uri":")"
          << image_uri << R"("}],)";
    j << R"("buffers":[{"byteLength":68)";
    if (!buffer_uri.empty()) j << R"(,"uri":")" << buffer_uri << '"';
    j << R"(}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24},
               {"buffer":0,"byteOffset":60,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
             {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"},
             {"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}]})";
    return j.str();
}

std::string data_uri(const std::string& bytes, const char* mime) { return std::string("data:") + mime + ";base64," + base64(bytes); }

std::string glb(std::string json, const std::string& bin) {
    while (json.size() % 4) json += ' ';
    std::string s = "glTF";
    put(s, std::uint32_t{2});
    put(s, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    put(s, static_cast<std::uint32_t>(json.size()));
    s += "JSON" + json;
    put(s, static_cast<std::uint32_t>(bin.size()));
    s += std::string("BIN\0", 4) + bin;
    return s;
}

// ---------------------------------------------------------------------------------------------
// Helpers: checks

bool mentions(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

Result<LoadedModel> load(const std::string& path, const LoadOptions& options = {}) { return load_model(path, options); }

// Loads a file that must fail; checks the code and that the message names the file.
Error expect_error(const std::string& path, ErrorCode code, const LoadOptions& options = {}) {
    Result<LoadedModel> r = load_model(path, options);
    EXPECT_FALSE(r.ok()) << path << " loaded";
    if (r.ok()) return {};
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_TRUE(mentions(r.error().message, path)) << r.error().message;
    return r.error();
}

void expect_vec_near(Vec3 got, Vec3 want, float tol = 1e-5f) {
    EXPECT_NEAR(got.x, want.x, tol);
    EXPECT_NEAR(got.y, want.y, tol);
    EXPECT_NEAR(got.z, want.z, tol);
}

// Every vertex normal is unit length and every object is well formed: an object with triangles has
// a normal per vertex; one of points or lines alone has them only when the file does.
void expect_well_formed(const Scene& scene) {
    for (const SceneObject& o : scene.objects) {
        EXPECT_TRUE(o.mesh.validate().ok());
        EXPECT_FALSE(o.mesh.indices.empty() && o.mesh.points.empty() && o.mesh.lines.empty());
        if (o.mesh.indices.empty() && o.mesh.normals.empty()) continue;
        ASSERT_EQ(o.mesh.normals.size(), o.mesh.positions.size());
        for (Vec3 n : o.mesh.normals) EXPECT_NEAR(length(n), 1.0f, 1e-4f);
    }
}

std::set<std::tuple<long, long, long>> distinct_normals(const Mesh& m) {
    std::set<std::tuple<long, long, long>> s;
    for (Vec3 n : m.normals) s.insert({std::lround(n.x * 1e4), std::lround(n.y * 1e4), std::lround(n.z * 1e4)});
    return s;
}

// Flat shading: each triangle's three vertex normals equal its face normal.
void expect_flat(const Mesh& m) {
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const Vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        const Vec3 face = normalize(cross(b - a, c - a));
        for (int k = 0; k < 3; ++k) expect_vec_near(m.normals[m.indices[t + k]], face, 1e-5f);
    }
}

long vm_peak_kb() {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmPeak:", 0) == 0) return std::stol(line.substr(7));
    return 0;
}

// Samples the texture at the centre of the texel quadrant a uv corner (0 or 1 per axis) lies in.
Rgba8 texel_at_corner(const Texture& t, Vec2 uv) {
    const Sampler nearest{Wrap::clamp, Wrap::clamp, Filter::nearest};
    return to_rgba8(t.sample_lod({0.25f + uv.x * 0.5f, 0.25f + uv.y * 0.5f}, 0, nearest));
}

// The vertex of a mesh at a position.
std::size_t vertex_at(const Mesh& m, Vec3 p) {
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        if (length(m.positions[i] - p) < 1e-6f) return i;
    ADD_FAILURE() << "no vertex at " << p.x << "," << p.y << "," << p.z;
    return 0;
}

// ---------------------------------------------------------------------------------------------
// Creased normals (facet's own code, include/facet/mesh.hpp)

TEST(CreasedNormals, UnindexedCubeGetsFlatFacesAt40Degrees) {
    const Mesh cube = split_faces_flat(make_cube(1));  // 36 vertices, shared only by position
    Mesh m;
    m.positions = cube.positions;
    m.indices = cube.indices;
    compute_creased_normals(m, radians(40));
    EXPECT_TRUE(m.validate().ok());
    EXPECT_EQ(m.positions.size(), 36u);  // splitting never merges
    EXPECT_EQ(distinct_normals(m).size(), 6u);
    expect_flat(m);
}

TEST(CreasedNormals, WeldedCubeSplitsInto24VerticesAndSmoothsAt180) {
    // Indexed cube with 8 shared corners: make_cube's 24 vertices welded by position.
    const Mesh cube = make_cube(1);
    Mesh m;
    for (std::uint32_t i : cube.indices) {
        const auto it = std::find(m.positions.begin(), m.positions.end(), cube.positions[i]);
        m.indices.push_back(static_cast<std::uint32_t>(it - m.positions.begin()));
        if (it == m.positions.end()) m.positions.push_back(cube.positions[i]);
    }
    ASSERT_EQ(m.positions.size(), 8u);
    m.uvs.assign(8, Vec2{0.5f, 0.25f});
    Mesh flat = m;
    compute_creased_normals(flat, radians(40));
    EXPECT_TRUE(flat.validate().ok());
    EXPECT_EQ(flat.positions.size(), 24u);
    EXPECT_EQ(flat.uvs.size(), 24u);
    for (Vec2 uv : flat.uvs) EXPECT_TRUE(uv == (Vec2{0.5f, 0.25f}));  // copies keep their attributes
    expect_flat(flat);

    compute_creased_normals(m, k_pi);  // 180 degrees: one normal per corner, along the diagonal
    EXPECT_EQ(m.positions.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) expect_vec_near(m.normals[i], normalize(m.positions[i]), 1e-5f);
}

TEST(CreasedNormals, SmoothSphereStaysSmoothAndMatchesSmoothNormals) {
    const Mesh sphere = make_icosphere(1, 3);
    Mesh creased = sphere, smooth = sphere;
    compute_creased_normals(creased, radians(40));
    compute_smooth_normals(smooth);
    ASSERT_EQ(creased.positions.size(), sphere.positions.size());  // no vertex split
    for (std::size_t i = 0; i < sphere.positions.size(); ++i) {
        expect_vec_near(creased.normals[i], smooth.normals[i], 1e-5f);
        EXPECT_GT(dot(creased.normals[i], normalize(sphere.positions[i])), 0.999f);
    }
}

TEST(CreasedNormals, DegenerateAndOutOfRangeTrianglesDoNotBreakIt) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {k_nan, 0, 0}};
    m.indices = {0, 1, 2, 3, 3, 3, 0, 1, 99, 0, 1, 4};
    compute_creased_normals(m, radians(40));
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t i = 0; i < 3; ++i) expect_vec_near(m.normals[i], {0, 0, 1});
    for (Vec3 n : m.normals) EXPECT_TRUE(is_finite(n));
    EXPECT_EQ(m.indices[8], 99u);  // left alone, as validate() reports it
    Mesh empty;
    compute_creased_normals(empty, 1.0f);
    EXPECT_TRUE(empty.normals.empty());
}

TEST(CreasedNormals, CylinderKeepsSmoothSidesAndSharpCaps) {
    // Closed 32-sided prism: sides meet at 11.25 degrees (smooth), caps at 90 (creased).
    Mesh m;
    const int n = 32;
    for (int i = 0; i < n; ++i) {
        const float a = 2 * k_pi * i / n;
        m.positions.push_back({std::cos(a), 0, -std::sin(a)});
        m.positions.push_back({std::cos(a), 1, -std::sin(a)});
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        m.indices.insert(m.indices.end(), {2 * i, 2 * j, 2 * j + 1, 2 * i, 2 * j + 1, 2 * i + 1});
        if (i > 0 && i + 1 < n) {
            m.indices.insert(m.indices.end(), {0, 2 * (i + 1), 2 * i});          // bottom cap, facing -y
            m.indices.insert(m.indices.end(), {1, 2 * i + 1, 2 * (i + 1) + 1});  // top cap, facing +y
        }
    }
    compute_creased_normals(m, radians(40));
    EXPECT_EQ(m.positions.size(), 4u * n);  // each ring vertex: one side normal, one cap normal
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3 p = m.positions[i], nrm = m.normals[i];
        const bool cap = std::abs(nrm.y) > 0.99f;
        if (cap) expect_vec_near(nrm, {0, p.y > 0.5f ? 1.f : -1.f, 0});
        else expect_vec_near(nrm, normalize(Vec3{p.x, 0, p.z}), 1e-4f);
    }
}

// ---------------------------------------------------------------------------------------------
// Generated files

TEST(ModelLoader, ObjQuadAndTriangleBecomeThreeTriangles) {
    const fs::path dir = temp_dir();
    const std::string path = write_file(dir / "shape.obj",
                                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 -2\n"
                                        "f 1 2 3 4\nf 1 5 2\n");
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty());
    ASSERT_EQ(r->scene.objects.size(), 1u);
    const SceneObject& o = r->scene.objects[0];
    EXPECT_TRUE(o.model == Mat4::identity());  // OBJ has no transforms
    EXPECT_EQ(o.mesh.triangle_count(), 3u);
    // 5 points; the two the quad shares with the triangle meet it at 90 degrees, so each gets a
    // second vertex for the other face's normal.
    EXPECT_EQ(o.mesh.positions.size(), 7u);
    const Aabb box = r->scene.bounds();
    expect_vec_near(box.min, {0, 0, -2});
    expect_vec_near(box.max, {1, 1, 0});
    expect_well_formed(r->scene);
    EXPECT_TRUE(o.mesh.colours.empty());
    EXPECT_TRUE(o.mesh.uvs.empty());
}

TEST(ModelLoader, ObjNormalsFromTheFileAreKept) {
    const fs::path dir = temp_dir();
    const std::string path = write_file(dir / "n.obj",
                                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0.6 0 0.8\n"
                                        "f 1//1 2//1 3//1\n");
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (Vec3 n : r->scene.objects[0].mesh.normals) expect_vec_near(n, {0.6f, 0, 0.8f});
}

TEST(ModelLoader, StlCubeGetsFlatFacesAt40DegreesAndCornersAt180) {
    const fs::path dir = temp_dir();
    const auto cube = triangles_of(make_cube(1));
    for (const std::string& path : {write_file(dir / "cube.stl", binary_stl(cube)), write_file(dir / "cube_ascii.stl", ascii_stl(cube))}) {
        SCOPED_TRACE(path);
        Result<LoadedModel> r = load(path);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE(r->warnings.empty());
        ASSERT_EQ(r->scene.objects.size(), 1u);
        const Mesh& m = r->scene.objects[0].mesh;
        EXPECT_EQ(m.triangle_count(), 12u);
        EXPECT_EQ(m.positions.size(), 24u);  // 8 corners welded, then split 3 ways at the 90-degree edges
        EXPECT_EQ(distinct_normals(m).size(), 6u);
        expect_flat(m);
        expect_well_formed(r->scene);

        LoadOptions smooth;
        smooth.crease_angle_degrees = 180;
        Result<LoadedModel> s = load(path, smooth);
        ASSERT_TRUE(s.ok());
        const Mesh& sm = s->scene.objects[0].mesh;
        EXPECT_EQ(sm.positions.size(), 8u);
        for (std::size_t i = 0; i < 8; ++i) expect_vec_near(sm.normals[i], normalize(sm.positions[i]), 1e-5f);
    }
}

TEST(ModelLoader, StlSphereStaysSmooth) {
    const fs::path dir = temp_dir();
    const Mesh sphere = make_icosphere(2, 3);  // neighbouring faces meet at about 8 degrees
    const std::string path = write_file(dir / "sphere.stl", binary_stl(triangles_of(sphere)));
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& m = r->scene.objects[0].mesh;
    EXPECT_EQ(m.triangle_count(), sphere.triangle_count());
    EXPECT_EQ(m.positions.size(), sphere.positions.size());  // welded, never split
    for (std::size_t i = 0; i < m.positions.size(); ++i) EXPECT_GT(dot(m.normals[i], normalize(m.positions[i])), 0.999f);
}

TEST(ModelLoader, PlyVertexColours) {
    const fs::path dir = temp_dir();
    const std::string path = write_file(dir / "c.ply",
                                        "ply\nformat ascii 1.0\nelement vertex 3\n"
                                        "property float x\nproperty float y\nproperty float z\n"
                                        "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                        "0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n0 1 0 0 0 255 255\n3 0 1 2\n");
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mesh& m = r->scene.objects[0].mesh;
    ASSERT_EQ(m.colours.size(), m.positions.size());
    const std::pair<Vec3, Vec4> want[] = {{{0, 0, 0}, {1, 0, 0, 1}}, {{1, 0, 0}, {0, 1, 0, 128 / 255.0f}}, {{0, 1, 0}, {0, 0, 1, 1}}};
    for (const auto& [p, c] : want) {
        const Vec4 got = m.colours[vertex_at(m, p)];
        for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(got[k], c[k], 1e-6f);
    }
}

TEST(ModelLoader, OffQuadAndTriangle) {
    const fs::path dir = temp_dir();
    const std::string path = write_file(dir / "q.off", "OFF\n# comment\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 3 4\n");
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->scene.triangle_count(), 3u);
    expect_vec_near(r->scene.bounds().max, {1, 1, 1});
}

TEST(ModelLoader, GltfNodeTransformsAreAccumulatedPerInstance) {
    const fs::path dir = temp_dir();
    write_file(dir / "tri.bin", triangle_buffer());
    const std::string path = write_file(dir / "scene.gltf", gltf_json("tri.bin"));
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty());
    ASSERT_EQ(r->scene.objects.size(), 2u);  // one mesh, placed by two nodes
    for (const SceneObject& o : r->scene.objects) {
        ASSERT_EQ(o.mesh.triangle_count(), 1u);
        vertex_at(o.mesh, {1, 0, 0});  // the mesh stays in its own space
    }
    // Node 1: T(1,2,3) * [Rz(+90), (5,0,0)]; node 2: T(1,2,3) * S(2).
    const Mat4 want1 = translate({1, 2, 3}) * translate({5, 0, 0}) * rotate_z(k_pi / 2);
    const Mat4 want2 = translate({1, 2, 3}) * scale(2.0f);
    const Mat4& m1 = r->scene.objects[0].model;
    const Mat4& m2 = r->scene.objects[1].model;
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            EXPECT_NEAR(m1(row, col), want1(row, col), 1e-6f) << row << "," << col;
            EXPECT_NEAR(m2(row, col), want2(row, col), 1e-6f) << row << "," << col;
        }
    expect_vec_near(transform_point(m1, {1, 0, 0}), {6, 3, 3});  // x -> y by the rotation
    expect_vec_near(transform_point(m1, {0, 1, 0}), {5, 2, 3});
    expect_vec_near(transform_point(m2, {1, 0, 0}), {3, 2, 3});
    // Material: base colour factor with its alpha, MASK with the cutoff, double sided.
    const Material& mat = r->scene.objects[0].material;
    expect_vec_near(mat.base_colour.xyz(), {0.5f, 0.25f, 1.0f});
    EXPECT_NEAR(mat.base_colour.w, 0.75f, 1e-6f);
    EXPECT_EQ(mat.alpha_mode, AlphaMode::mask);
    EXPECT_NEAR(mat.alpha_cutoff, 0.3f, 1e-6f);
    EXPECT_TRUE(mat.double_sided);
    EXPECT_EQ(mat.base_colour_texture, nullptr);

    // The same document as GLB, and with the buffer embedded as a data URI.
    for (const std::string& p : {write_file(dir / "scene.glb", glb(gltf_json(""), triangle_buffer())),
                                 write_file(dir / "embedded.gltf", gltf_json(data_uri(triangle_buffer(), "application/octet-stream")))}) {
        Result<LoadedModel> g = load(p);
        ASSERT_TRUE(g.ok()) << g.error().message;
        ASSERT_EQ(g->scene.objects.size(), 2u);
        expect_vec_near(transform_point(g->scene.objects[0].model, {1, 0, 0}), {6, 3, 3});
    }
}

TEST(ModelLoader, UpAxisZTurnsPlusZIntoPlusY) {
    const fs::path dir = temp_dir();
    const std::string path = write_file(dir / "z.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
    LoadOptions z_up;
    z_up.up_axis = UpAxis::z;
    Result<LoadedModel> r = load(path, z_up);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Mat4& model = r->scene.objects[0].model;
    expect_vec_near(transform_point(model, {1, 0, 0}), {1, 0, 0});
    expect_vec_near(transform_point(model, {0, 0, 1}), {0, 1, 0});
    expect_vec_near(transform_point(model, {0, 1, 0}), {0, 0, -1});
    EXPECT_NEAR(determinant(model), 1.0f, 1e-6f);  // a rotation: handedness kept
    // The up axis composes with node transforms: it is applied last (outermost).
    write_file(dir / "tri.bin", triangle_buffer());
    Result<LoadedModel> g = load(write_file(dir / "scene.gltf", gltf_json("tri.bin")), z_up);
    ASSERT_TRUE(g.ok());
    expect_vec_near(transform_point(g->scene.objects[1].model, {1, 0, 0}), {3, 3, -2});  // (3,2,3) -> (3,3,-2)
}

TEST(ModelLoader, GltfEmbeddedTextureKeepsTopLeftUvOriginAndWrapModes) {
    const fs::path dir = temp_dir();
    const std::string png = read_file(write_test_png(dir / "t.png"));
    const std::string path = write_file(dir / "tex.gltf", gltf_json(data_uri(triangle_buffer(), "application/octet-stream"),
                                                                    data_uri(png, "image/png")));
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty()) << r->warnings[0];
    const SceneObject& o = r->scene.objects[0];
    ASSERT_NE(o.material.base_colour_texture, nullptr);
    const Texture& t = *o.material.base_colour_texture;
    EXPECT_EQ(t.width(), 2);
    EXPECT_EQ(t.height(), 2);
    EXPECT_EQ(o.material.sampler.wrap_u, Wrap::clamp);
    EXPECT_EQ(o.material.sampler.wrap_v, Wrap::mirror);
    // glTF uv (0,0) is the image's top-left texel, (1,0) top-right, (0,1) bottom-left.
    ASSERT_EQ(o.mesh.uvs.size(), o.mesh.positions.size());
    EXPECT_EQ(texel_at_corner(t, o.mesh.uvs[vertex_at(o.mesh, {0, 0, 0})]), k_red);
    EXPECT_EQ(texel_at_corner(t, o.mesh.uvs[vertex_at(o.mesh, {1, 0, 0})]), k_green);
    EXPECT_EQ(texel_at_corner(t, o.mesh.uvs[vertex_at(o.mesh, {0, 1, 0})]), k_blue);
}

// OBJ materials: colour and opacity, textures named the Windows way, in another letter case, by an
// absolute path from another machine, missing, or not an image.
TEST(ModelLoader, ObjMaterialsAndLenientTexturePaths) {
    const fs::path dir = temp_dir();
    write_test_png(dir / "tex.png");
    write_file(dir / "broken.png", "this is not a PNG file at all");
    write_file(dir / "m.mtl",
               "newmtl windows\nKd 0.2 0.4 0.6\nd 0.5\nmap_Kd .\\TEX.PNG\n"
               "newmtl absolute\nKd 1 1 1\nmap_Kd C:\\Users\\someone\\textures\\tex.png\n"
               "newmtl missing\nKd 0.9 0.1 0.1\nmap_Kd missing_texture.png\n"
               "newmtl broken\nKd 1 1 1\nmap_Kd broken.png\n");
    const std::string path = write_file(dir / "m.obj",
                                        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                        "usemtl windows\nf 1/1 2/2 3/3\nusemtl absolute\nf 1/1 2/2 3/3\n"
                                        "usemtl missing\nf 1/1 2/2 3/3\nusemtl broken\nf 1/1 2/2 3/3\n");
    Result<LoadedModel> r = load(path);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->scene.objects.size(), 4u);
    const SceneObject &windows = r->scene.objects[0], &absolute = r->scene.objects[1], &missing = r->scene.objects[2],
                      &broken = r->scene.objects[3];
    expect_vec_near(windows.material.base_colour.xyz(), {0.2f, 0.4f, 0.6f});
    EXPECT_NEAR(windows.material.base_colour.w, 0.5f, 1e-6f);
    EXPECT_EQ(windows.material.alpha_mode, AlphaMode::blend);  // not opaque
    EXPECT_EQ(absolute.material.alpha_mode, AlphaMode::opaque);
    ASSERT_NE(windows.material.base_colour_texture, nullptr);
    ASSERT_NE(absolute.material.base_colour_texture, nullptr);
    EXPECT_EQ(missing.material.base_colour_texture, nullptr);
    expect_vec_near(missing.material.base_colour.xyz(), {0.9f, 0.1f, 0.1f});  // the fallback
    EXPECT_EQ(broken.material.base_colour_texture, nullptr);

    // OBJ's vt (0,0) is the image's bottom-left texel (OpenGL convention): after the flip it samples blue.
    const Texture& t = *windows.material.base_colour_texture;
    EXPECT_EQ(texel_at_corner(t, windows.mesh.uvs[vertex_at(windows.mesh, {0, 0, 0})]), k_blue);
    EXPECT_EQ(texel_at_corner(t, windows.mesh.uvs[vertex_at(windows.mesh, {1, 0, 0})]), k_white);
    EXPECT_EQ(texel_at_corner(t, windows.mesh.uvs[vertex_at(windows.mesh, {0, 1, 0})]), k_red);

    // One warning per bad texture, naming the model and the texture.
    ASSERT_EQ(r->warnings.size(), 2u);
    EXPECT_TRUE(mentions(r->warnings[0], path) && mentions(r->warnings[0], "missing_texture.png")) << r->warnings[0];
    EXPECT_TRUE(mentions(r->warnings[1], path) && mentions(r->warnings[1], "broken.png")) << r->warnings[1];
}

TEST(ModelLoader, SupportedExtensions) {
    EXPECT_TRUE(is_supported_model_file("a/b/model.obj"));
    EXPECT_TRUE(is_supported_model_file("MODEL.STL"));
    for (const char* ext : {"ply", "off", "gltf", "glb", "fbx", "3mf", "dae", "3ds"}) EXPECT_TRUE(is_supported_model_file(std::string("x.") + ext)) << ext;
    EXPECT_TRUE(is_supported_model_file("points.xyz"));  // point clouds (point_cloud_test.cpp)
    EXPECT_FALSE(is_supported_model_file("table.csv"));
    EXPECT_FALSE(is_supported_model_file("picture.png"));
    EXPECT_FALSE(is_supported_model_file("no_extension"));
    // facet's own parsers: OFF, STL and PLY, by the extension in any case.
    EXPECT_TRUE(has_own_parser("a/b/bunny.off"));
    EXPECT_TRUE(has_own_parser("BUNNY.OFF"));
    EXPECT_TRUE(has_own_parser("part.stl"));
    EXPECT_TRUE(has_own_parser("PART.STL"));
    EXPECT_TRUE(has_own_parser("scan.ply"));
    for (const char* other : {"x.obj", "x.glb", "x.offx", "x.stlx", "off", "stl", "ply", "no_extension"}) EXPECT_FALSE(has_own_parser(other)) << other;
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(ModelLoaderErrors, MissingFileAndDirectory) {
    const fs::path dir = temp_dir();
    const Error missing = expect_error((dir / "nope.obj").string(), ErrorCode::io);
    EXPECT_TRUE(mentions(missing.message, "no such file")) << missing.message;
    fs::create_directories(dir / "folder.obj");
    const Error folder = expect_error((dir / "folder.obj").string(), ErrorCode::io);
    EXPECT_TRUE(mentions(folder.message, "directory")) << folder.message;
}

TEST(ModelLoaderErrors, UnreadableFile) {
    const fs::path dir = temp_dir();
    const std::string locked = write_file(dir / "locked.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::permissions(locked, fs::perms::none);
    if (geteuid() == 0) GTEST_SKIP() << "running as root: file permissions do not stop reads";
    expect_error(locked, ErrorCode::io);
}

TEST(ModelLoaderErrors, UnknownFormatAndEmptyFiles) {
    const fs::path dir = temp_dir();
    expect_error(write_file(dir / "cloud.csv", "1,2,3\n4,5,6\n"), ErrorCode::unsupported);
    expect_error(write_file(dir / "noext", "v 0 0 0\n"), ErrorCode::unsupported);
    for (const char* ext : {"obj", "stl", "ply", "off", "gltf", "glb", "fbx", "3mf", "dae"}) {
        const Error e = expect_error(write_file(dir / (std::string("empty.") + ext), ""), ErrorCode::bad_format);
        EXPECT_TRUE(mentions(e.message, "empty")) << e.message;
    }
}

TEST(ModelLoaderErrors, GarbageWithModelExtensions) {
    const fs::path dir = temp_dir();
    for (unsigned seed = 1; seed <= 3; ++seed) {
        std::mt19937 rng(seed);
        std::string bytes(4000, '\0');
        for (char& c : bytes) c = static_cast<char>(rng());
        for (const char* ext : {"obj", "stl", "ply", "off", "gltf", "glb", "fbx", "3mf", "dae", "3ds", "x"}) {
            const std::string path = write_file(dir / ("garbage" + std::to_string(seed) + "." + ext), bytes);
            SCOPED_TRACE(path);
            expect_error(path, ErrorCode::bad_format);
        }
    }
}

TEST(ModelLoaderErrors, TruncatedFiles) {
    const fs::path dir = temp_dir();
    const Mesh sphere = make_icosphere(1, 2);
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(sphere.positions.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(sphere.triangle_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (Vec3 p : sphere.positions) put(ply, p.x), put(ply, p.y), put(ply, p.z);
    for (std::size_t t = 0; t < sphere.indices.size(); t += 3) {
        put(ply, std::uint8_t{3});
        for (int k = 0; k < 3; ++k) put(ply, static_cast<std::int32_t>(sphere.indices[t + k]));
    }
    std::ostringstream ascii_ply;
    ascii_ply << "ply\nformat ascii 1.0\nelement vertex " << sphere.positions.size()
              << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << sphere.triangle_count() / 2
              << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (Vec3 p : sphere.positions) ascii_ply << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (std::size_t t = 0; t + 5 < sphere.indices.size(); t += 6)  // quads, so triangulation runs
        ascii_ply << "4 " << sphere.indices[t] << ' ' << sphere.indices[t + 1] << ' ' << sphere.indices[t + 2] << ' '
                  << sphere.indices[t + 5] << '\n';
    const std::pair<const char*, std::string> whole[] = {
        {"cut.stl", binary_stl(triangles_of(sphere))},
        {"cut_solid.stl", binary_stl(triangles_of(sphere), "solid, but binary")},  // as many exporters write
        {"cut.ply", ply},
        {"cut_ascii.ply", ascii_ply.str()},
        {"cut.glb", glb(gltf_json(""), triangle_buffer())},
    };
    for (const auto& [name, bytes] : whole) {
        ASSERT_TRUE(load(write_file(dir / (std::string("whole_") + name), bytes)).ok()) << name;
        const std::string path = write_file(dir / name, bytes.substr(0, bytes.size() / 2));
        SCOPED_TRACE(path);
        expect_error(path, ErrorCode::bad_format);
    }
    // A real ASCII PLY cut in half used to trip an assertion inside assimp's triangulation
    // (abort); facet turns it into an error.
    const fs::path wuson = k_assimp_models / "PLY" / "Wuson.ply";
    if (fs::exists(wuson)) {
        const std::string bytes = read_file(wuson);
        const Error e = expect_error(write_file(dir / "wuson_cut.ply", bytes.substr(0, bytes.size() / 2)), ErrorCode::bad_format);
        EXPECT_TRUE(mentions(e.message, "assimp")) << e.message;
    }
}

// Headers claiming 10^12 elements must fail at once: assimp would reserve memory for them
// (an OFF claiming 3.5e11 vertices costs it 40 s and 16 GB of address space).
TEST(ModelLoaderErrors, HugeHeaderCountsFailFastWithoutAllocating) {
    const fs::path dir = temp_dir();
    std::string stl(80, ' ');
    put(stl, std::uint32_t{0xFFFFFFFF});
    stl += std::string(200, '\0');
    const std::string files[] = {
        write_file(dir / "huge_ascii.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        write_file(dir / "huge_binary.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n" + std::string(64, '\0')),
        write_file(dir / "huge_faces.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 99999999999999\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        write_file(dir / "huge.stl", stl),
        write_file(dir / "huge_vertices.off", "OFF\n1000000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        write_file(dir / "huge_faces.off", "OFF\n3 1000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        write_file(dir / "overflow.off", "OFF\n3 99999999999999999999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
    };
    const long peak_before = vm_peak_kb();
    for (const std::string& path : files) {
        SCOPED_TRACE(path);
        const auto start = std::chrono::steady_clock::now();
        expect_error(path, ErrorCode::bad_format);
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
    }
    EXPECT_LT(vm_peak_kb() - peak_before, 256 * 1024) << "address space grew by more than 256 MB";
}

TEST(ModelLoaderErrors, IndicesOutOfRange) {
    const fs::path dir = temp_dir();
    expect_error(write_file(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), ErrorCode::bad_format);
    expect_error(write_file(dir / "bad.ply",
                            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
                 ErrorCode::bad_format);
    // OFF: assimp's reader clamps the index to the last vertex and only logs an error; facet reports it.
    const Error off = expect_error(write_file(dir / "bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"), ErrorCode::bad_format);
    EXPECT_TRUE(mentions(off.message, "out of range")) << off.message;
    // glTF: assimp's reader drops the faces that index past the vertices.
    write_file(dir / "tri.bin", triangle_buffer(9));
    Result<LoadedModel> g = load(write_file(dir / "bad.gltf", gltf_json("tri.bin")));
    EXPECT_FALSE(g.ok());
}

TEST(ModelLoaderErrors, NonFiniteCoordinatesDropTrianglesWithAWarning) {
    const fs::path dir = temp_dir();
    const std::array<Vec3, 3> good = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};
    const std::array<Vec3, 3> nan = {Vec3{0, 0, 0}, Vec3{k_nan, 0, 0}, Vec3{0, 1, 0}};
    const std::array<Vec3, 3> inf = {Vec3{0, 0, 5}, Vec3{1, 0, 5}, Vec3{0, k_inf, 5}};
    const std::string some = write_file(dir / "some.stl", binary_stl({nan, good, inf}));
    Result<LoadedModel> r = load(some);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->scene.triangle_count(), 1u);
    for (Vec3 p : r->scene.objects[0].mesh.positions) EXPECT_TRUE(is_finite(p));
    expect_well_formed(r->scene);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_TRUE(mentions(r->warnings[0], some) && mentions(r->warnings[0], "dropped 2")) << r->warnings[0];

    const Error e = expect_error(write_file(dir / "all.stl", binary_stl({nan, inf})), ErrorCode::bad_format);
    EXPECT_TRUE(mentions(e.message, "no valid triangles")) << e.message;
}

// Files of points or lines alone load as such (issue 26: they used to be "contains no triangles");
// a file of degenerate triangles alone is still an error.
TEST(ModelLoaderErrors, NoTriangles) {
    const fs::path dir = temp_dir();
    for (const auto& [path, points, segments] :
         {std::tuple{write_file(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n"), 3, 0},
          std::tuple{write_file(dir / "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n"), 0, 2},
          std::tuple{write_file(dir / "vertices.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), 3, 0}}) {
        SCOPED_TRACE(path);
        Result<LoadedModel> r = load(path);
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_EQ(r->scene.objects.size(), 1u);
        EXPECT_EQ(r->scene.triangle_count(), 0u);
        EXPECT_EQ(r->scene.objects[0].mesh.points.size(), static_cast<std::size_t>(points));
        EXPECT_EQ(r->scene.objects[0].mesh.lines.size(), static_cast<std::size_t>(2 * segments));
    }
    const Error e = expect_error(write_file(dir / "degenerate.off", "OFF\n1 2 0\n0 0 0\n3 0 0 0\n3 0 0 0\n"), ErrorCode::bad_format);
    EXPECT_TRUE(mentions(e.message, "triangles")) << e.message;
}

TEST(ModelLoaderErrors, Limits) {
    const fs::path dir = temp_dir();
    const std::string obj = write_file(dir / "two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    LoadOptions small_file;
    small_file.max_file_bytes = 10;
    expect_error(obj, ErrorCode::limit_exceeded, small_file);
    LoadOptions one_triangle;
    one_triangle.max_triangles = 1;
    expect_error(obj, ErrorCode::limit_exceeded, one_triangle);
    // Instances count: one triangle placed twice is two.
    write_file(dir / "tri.bin", triangle_buffer());
    expect_error(write_file(dir / "twice.gltf", gltf_json("tri.bin")), ErrorCode::limit_exceeded, one_triangle);
    // From headers, before assimp reads anything.
    const auto sphere = triangles_of(make_icosphere(1, 1));  // 80 triangles
    LoadOptions ten;
    ten.max_triangles = 10;
    const Error stl = expect_error(write_file(dir / "sphere.stl", binary_stl(sphere)), ErrorCode::limit_exceeded, ten);
    EXPECT_TRUE(mentions(stl.message, "80 triangles")) << stl.message;
    std::string off = "OFF\n3 11 0\n0 0 0\n1 0 0\n0 1 0\n";
    for (int i = 0; i < 11; ++i) off += "3 0 1 2\n";
    expect_error(write_file(dir / "faces.off", off), ErrorCode::limit_exceeded, ten);
}

// ---------------------------------------------------------------------------------------------
// Real files

#define REQUIRE_ASSIMP_MODELS() FACET_REQUIRE_ASSIMP_MODELS()

// Every file in assimp's folder of malformed files fails with an error naming it, or loads a valid scene.
TEST(ModelLoaderRealFiles, AssimpInvalidFolderNeverCrashes) {
    REQUIRE_ASSIMP_MODELS();
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(k_assimp_models / "invalid"))
        if (e.is_regular_file()) files.push_back(e.path());
    files.push_back(k_assimp_models / "OFF" / "invalid.off");
    ASSERT_GE(files.size(), 10u);
    std::size_t errors = 0;
    for (const fs::path& f : files) {
        SCOPED_TRACE(f.string());
        const auto start = std::chrono::steady_clock::now();
        Result<LoadedModel> r = load(f.string());
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
        if (r.ok()) {
            // malformed2.obj names a material that does not exist: a warning says so.
            // OFF/invalid.off has only degenerate triangles (an error alone) and a one-index face,
            // which assimp reads as a point: that point is drawn.
            expect_well_formed(r->scene);
            EXPECT_FALSE(r->warnings.empty());
        } else {
            ++errors;
            EXPECT_TRUE(mentions(r.error().message, f.string())) << r.error().message;
        }
    }
    EXPECT_GE(errors, files.size() - 2);
    const Error oom = expect_error((k_assimp_models / "invalid" / "OutOfMemory.off").string(), ErrorCode::bad_format);
    EXPECT_TRUE(mentions(oom.message, "353535235358")) << oom.message;
}

// The whole test corpus (about 600 files in 50 formats): each loads a well-formed scene or
// fails with an error naming it; nothing crashes or hangs.
TEST(ModelLoaderRealFiles, EveryAssimpTestModelLoadsOrFailsCleanly) {
    REQUIRE_ASSIMP_MODELS();
    std::size_t loaded = 0, failed = 0;
    for (const auto& e : fs::recursive_directory_iterator(k_assimp_models)) {
        if (!e.is_regular_file()) continue;
        const std::string path = e.path().string();
        SCOPED_TRACE(path);
        Result<LoadedModel> r = load(path);
        if (r.ok()) {
            ++loaded;
            expect_well_formed(r->scene);  // each object has triangles, points or lines
            for (const std::string& w : r->warnings) EXPECT_TRUE(mentions(w, path)) << w;
        } else {
            ++failed;
            EXPECT_TRUE(mentions(r.error().message, path)) << r.error().message;
        }
    }
    EXPECT_GT(loaded, 250u);
    std::printf("[          ] assimp test models: %zu loaded, %zu refused\n", loaded, failed);
}

TEST(ModelLoaderRealFiles, SpiderObjWithTextures) {
    REQUIRE_ASSIMP_MODELS();
    const fs::path path = k_assimp_models / "OBJ" / "spider.obj";
    // Independent counts from the file: every face line has three vertices.
    std::ifstream in(path);
    std::size_t faces = 0;
    std::vector<Vec2> file_uvs;
    for (std::string line; std::getline(in, line);) {
        std::istringstream words(line);
        std::string tag;
        words >> tag;
        if (tag == "f") {
            ++faces;
            std::size_t corners = 0;
            for (std::string w; words >> w;) ++corners;
            ASSERT_EQ(corners, 3u);
        } else if (tag == "vt") {
            Vec2 uv;
            words >> uv.x >> uv.y;
            file_uvs.push_back(uv);
        }
    }
    Result<LoadedModel> r = load(path.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty()) << r->warnings[0];  // ".\\SpiderTex.jpg" and friends are found
    EXPECT_EQ(r->scene.triangle_count(), faces);
    EXPECT_EQ(faces, 1368u);
    expect_well_formed(r->scene);
    for (const SceneObject& o : r->scene.objects) {
        EXPECT_NE(o.material.base_colour_texture, nullptr);
        // Each uv is a vt of the file with v flipped to the top-left origin.
        for (Vec2 uv : o.mesh.uvs) {
            const bool found = std::any_of(file_uvs.begin(), file_uvs.end(), [&](Vec2 f) {
                return std::abs(f.x - uv.x) < 1e-5f && std::abs((1 - f.y) - uv.y) < 1e-5f;
            });
            EXPECT_TRUE(found) << uv.x << "," << uv.y;
            if (!found) break;
        }
    }
}

TEST(ModelLoaderRealFiles, BoxTexturedGltfGlbAndEmbedded) {
    REQUIRE_ASSIMP_MODELS();
    const fs::path files[] = {k_assimp_models / "glTF2" / "BoxTextured-glTF" / "BoxTextured.gltf",
                              k_assimp_models / "glTF2" / "BoxTextured-glTF-Binary" / "BoxTextured.glb",
                              k_assimp_models / "glTF2" / "BoxTextured-glTF-Embedded" / "BoxTextured.gltf"};
    // The separate-files version samples with MIRRORED_REPEAT (S) and CLAMP_TO_EDGE (T), the
    // others with REPEAT.
    const Wrap want_u[] = {Wrap::mirror, Wrap::repeat, Wrap::repeat}, want_v[] = {Wrap::clamp, Wrap::repeat, Wrap::repeat};
    std::vector<Vec2> first_uvs;
    for (std::size_t i = 0; i < std::size(files); ++i) {
        const fs::path& f = files[i];
        SCOPED_TRACE(f.string());
        Result<LoadedModel> r = load(f.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE(r->warnings.empty());
        ASSERT_EQ(r->scene.objects.size(), 1u);
        const SceneObject& o = r->scene.objects[0];
        EXPECT_EQ(o.mesh.triangle_count(), 12u);  // the indices accessor has 36 entries
        expect_vec_near(r->scene.bounds().min, {-0.5f, -0.5f, -0.5f});
        expect_vec_near(r->scene.bounds().max, {0.5f, 0.5f, 0.5f});
        ASSERT_NE(o.material.base_colour_texture, nullptr);
        EXPECT_EQ(o.material.base_colour_texture->width(), 211);  // CesiumLogoFlat.png
        EXPECT_EQ(o.material.sampler.wrap_u, want_u[i]);
        EXPECT_EQ(o.material.sampler.wrap_v, want_v[i]);
        EXPECT_FALSE(o.material.double_sided);
        EXPECT_EQ(o.material.alpha_mode, AlphaMode::opaque);
        expect_well_formed(r->scene);
        if (first_uvs.empty()) first_uvs = o.mesh.uvs;
        EXPECT_TRUE(o.mesh.uvs == first_uvs);  // three packagings of the same data
    }
}

TEST(ModelLoaderRealFiles, CesiumMilkTruck) {
    REQUIRE_ASSIMP_MODELS();
    const fs::path path = k_assimp_models / "glTF" / "CesiumMilkTruck" / "CesiumMilkTruck.gltf";
    Result<LoadedModel> r = load(path.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty());
    // From the JSON: mesh001 (a wheel pair, 768 triangles) is placed by two nodes, mesh002 (the
    // body, 2088 triangles in three primitives) by one: 2 * 768 + 2088.
    EXPECT_EQ(r->scene.triangle_count(), 3624u);
    std::size_t textured = 0;
    for (const SceneObject& o : r->scene.objects) textured += o.material.base_colour_texture != nullptr;
    EXPECT_GE(textured, 1u);
    expect_well_formed(r->scene);
}

// Binary STL: the triangle count is in the header, the bounds are the file's coordinates.
TEST(ModelLoaderRealFiles, BinaryStl) {
    REQUIRE_ASSIMP_MODELS();
    for (const char* name : {"Spider_binary.stl", "Wuson.stl"}) {
        const fs::path path = k_assimp_models / "STL" / name;
        SCOPED_TRACE(path.string());
        const std::string bytes = read_file(path);
        std::uint32_t n = 0;
        std::memcpy(&n, bytes.data() + 80, 4);
        ASSERT_EQ(84 + 50 * std::size_t{n}, bytes.size());
        Aabb box;
        for (std::size_t t = 0; t < n; ++t)
            for (int k = 0; k < 3; ++k) {
                Vec3 p;
                std::memcpy(&p, bytes.data() + 84 + 50 * t + 12 + 12 * k, 12);
                box.extend(p);
            }
        Result<LoadedModel> r = load(path.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE(r->warnings.empty());
        EXPECT_EQ(r->scene.triangle_count(), n);
        expect_vec_near(r->scene.bounds().min, box.min);
        expect_vec_near(r->scene.bounds().max, box.max);
        expect_well_formed(r->scene);
    }
}

TEST(ModelLoaderRealFiles, ColouredPly) {
    REQUIRE_ASSIMP_MODELS();
    const fs::path path = k_assimp_models / "PLY" / "float-color.ply";
    // After end_header: "x y z r g b a" per vertex (floats), then one face.
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {}
    std::vector<std::pair<Vec3, Vec4>> want;
    for (int i = 0; i < 3 && std::getline(in, line); ++i) {
        std::istringstream v(line);
        Vec3 p;
        Vec4 c;
        v >> p.x >> p.y >> p.z >> c.x >> c.y >> c.z >> c.w;
        want.push_back({p, c});
    }
    Result<LoadedModel> r = load(path.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->scene.triangle_count(), 1u);
    const Mesh& m = r->scene.objects[0].mesh;
    ASSERT_EQ(m.colours.size(), m.positions.size());
    for (const auto& [p, c] : want) {
        const Vec4 got = m.colours[vertex_at(m, p)];
        for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(got[k], c[k], 1e-6f);
    }
}

TEST(ModelLoaderRealFiles, ThreeMfBox) {
    REQUIRE_ASSIMP_MODELS();
    Result<LoadedModel> r = load((k_assimp_models / "3MF" / "box.3mf").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->scene.triangle_count(), 12u);
    expect_well_formed(r->scene);
}

TEST(ModelLoaderRealFiles, CgalOffMeshes) {
    const std::optional<fs::path> dir = cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    for (const char* name : {"bunny00.off", "armadillo.off", "elephant.off"}) {
        const fs::path path = *dir / name;
        SCOPED_TRACE(path.string());
        // Read the OFF here: counts, vertex bounds, triangles after fanning each face.
        std::ifstream in(path);
        std::string magic;
        std::size_t vertices = 0, faces = 0, edges = 0, triangles = 0;
        in >> magic >> vertices >> faces >> edges;
        ASSERT_EQ(magic, "OFF");
        Aabb box;
        for (std::size_t i = 0; i < vertices; ++i) {
            Vec3 p;
            in >> p.x >> p.y >> p.z;
            box.extend(p);
        }
        for (std::size_t f = 0; f < faces; ++f) {
            std::size_t n = 0;
            in >> n;
            triangles += n - 2;
            for (std::size_t k = 0; k < n; ++k) in >> edges;
        }
        ASSERT_TRUE(in) << "could not parse " << path;
        Result<LoadedModel> r = load(path.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE(r->warnings.empty());
        EXPECT_EQ(r->scene.triangle_count(), triangles);
        expect_vec_near(r->scene.bounds().min, box.min, 1e-4f);
        expect_vec_near(r->scene.bounds().max, box.max, 1e-4f);
        expect_well_formed(r->scene);
    }
}

}  // namespace

// allow_assimp_imports(false) (facet thumbs' serving workers): a file that needs assimp's importer
// is refused unread and counted; facet's own readers go on; allowed again, the same file loads.
namespace {
TEST(AssimpImports, RefusedWhileNotAllowedCountedAndLoadedOnceAllowed) {
    const fs::path dir = temp_dir();
    const std::string tetrahedron = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
    const std::string own = facet_test::write_file(dir / "own.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + tetrahedron);
    // NOFF (normals): facet's OFF reader leaves the file to assimp.
    const std::string quad = facet_test::write_file(
        dir / "quad.off", "NOFF\n4 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n");
    const std::size_t before = assimp_import_count();
    allow_assimp_imports(false);
    const Result<LoadedModel> refused = load_model(quad);
    const Result<LoadedModel> read_by_facet = load_model(own);
    allow_assimp_imports(true);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().code, ErrorCode::unsupported);
    EXPECT_NE(refused.error().message.find("left to a fresh process"), std::string::npos) << refused.error().message;
    EXPECT_TRUE(read_by_facet);
    EXPECT_EQ(assimp_import_count(), before + 1);
    const Result<LoadedModel> loaded = load_model(quad);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->scene.triangle_count(), 2u);
    EXPECT_EQ(assimp_import_count(), before + 2);
}
}  // namespace
