// Regression tests for hostile input: each fuzzing finding (docs/RELIABILITY.md, "Findings") and
// each hostile-input class added with the fuzzers, as an input that once crashed, hung or broke an
// invariant, and the outcome the library promises for it now (an Error with its code, or a
// result within the documented bounds). Inputs from the fuzzers live in tests/regression/<target>/
// and are replayed through the same calls the fuzz targets make.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "facet/model.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "facet/texture.hpp"
#include "support/paths.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::base64;

const fs::path k_regression_dir = fs::path(facet_test::k_source_dir) / "tests" / "regression";

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A glTF whose one mesh (`triangles` triangles, unindexed) is placed by `instances` nodes.
std::string instanced_gltf(int triangles, int instances) {
    std::string buffer;
    for (int t = 0; t < triangles; ++t)
        for (float v : {0.0f, 0.0f, float(t), 1.0f, 0.0f, float(t), 0.0f, 1.0f, float(t)})
            buffer.append(reinterpret_cast<const char*>(&v), sizeof v);
    std::ostringstream nodes, list;
    for (int i = 0; i < instances; ++i) {
        nodes << (i ? "," : "") << R"({"mesh":0,"translation":[)" << i * 2 << ",0,0]}";
        list << (i ? "," : "") << i;
    }
    std::ostringstream g;
    g << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)" << list.str() << R"(]}],"nodes":[)" << nodes.str()
      << R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
      << R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" << 3 * triangles
      << R"(,"type":"VEC3","min":[0,0,0],"max":[1,1,)" << triangles << R"(]}],)"
      << R"("bufferViews":[{"buffer":0,"byteLength":)" << buffer.size() << R"(}],)"
      << R"("buffers":[{"byteLength":)" << buffer.size() << R"(,"uri":"data:application/octet-stream;base64,)"
      << base64(buffer) << R"("}]})";
    return g.str();
}

// Every file in tests/regression/<target>/, in name order.
std::vector<fs::path> inputs_of(const std::string& target) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(k_regression_dir / target, ec))
        if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

// ---- resource limits ------------------------------------------------------------------------------

// A small file that places one mesh many times would be copied once per instance: the estimate of
// the converted scene is checked against max_scene_bytes before any copy is made.
TEST(Regression, InstancingAMeshManyTimesIsHeldToTheSceneMemoryLimit) {
    const fs::path dir = facet_test::test_temp_dir("facet_regression");
    const std::string once = (dir / "once.gltf").string(), many = (dir / "many.gltf").string();
    write_bytes(once, instanced_gltf(100, 1));
    write_bytes(many, instanced_gltf(100, 1000));

    // The estimate for one instance, from the error at a limit of one byte.
    LoadOptions tiny;
    tiny.max_scene_bytes = 1;
    const auto refused = load_model(once, tiny);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::limit_exceeded);
    const std::string& m = refused.error().message;
    ASSERT_TRUE(mentions(m, "would take at least ")) << m;
    const std::uint64_t one = std::stoull(m.substr(m.find("at least ") + 9));
    EXPECT_GE(one, 300u * 12u + 100u * 12u);  // at least positions and indices

    LoadOptions limit;
    limit.max_scene_bytes = static_cast<std::size_t>(one) * 10;
    EXPECT_TRUE(load_model(once, limit).ok());
    const auto bomb = load_model(many, limit);
    ASSERT_FALSE(bomb.ok());
    EXPECT_EQ(bomb.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(bomb.error().message, "more than the limit of " + std::to_string(one * 10))) << bomb.error().message;
    // With the default limit, 1000 small instances are fine.
    const auto fine = load_model(many);
    ASSERT_TRUE(fine.ok()) << fine.error().message;
    EXPECT_EQ(fine->scene.objects.size(), 1000u);
}

// ---- replayed fuzzer inputs ------------------------------------------------------------------------

// fuzz/texture_fuzzer: a BMP header that stb_image decodes "successfully" to a 0-pixel image; the
// copy into the Image passed a null pointer to memcpy (UBSan) and the empty Image then made the
// Texture constructor throw out of decode, which promises a Result.
TEST(Regression, BmpDecodingToNoPixelsIsABadFormatError) {
    const std::string bytes = read_bytes(k_regression_dir / "texture" / "bmp_zero_width.bmp");
    ASSERT_FALSE(bytes.empty());
    Result<std::shared_ptr<const Texture>> t = Texture::decode(bytes.data(), bytes.size(), "zero.bmp");
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().code, ErrorCode::bad_format);
    EXPECT_TRUE(mentions(t.error().message, "zero.bmp")) << t.error().message;
    EXPECT_TRUE(mentions(t.error().message, "without pixels")) << t.error().message;
}

// Every saved texture_fuzzer input, as the fuzzer runs it: an Error or a texture within the
// limits whose samples are in [0, 1]; never an exception.
TEST(Regression, TextureFuzzerInputsDecodeOrFailCleanly) {
    const std::vector<fs::path> inputs = inputs_of("texture");
    ASSERT_FALSE(inputs.empty());
    const TextureLimits limits{.max_size = 1024, .max_pixels = 128 * 128};
    for (const fs::path& input : inputs) {
        const std::string bytes = read_bytes(input);
        Result<std::shared_ptr<const Texture>> t = Texture::decode(bytes.data(), bytes.size(), input.string(), limits);
        if (!t.ok()) {
            EXPECT_TRUE(t.error().code == ErrorCode::bad_format || t.error().code == ErrorCode::limit_exceeded) << input;
            continue;
        }
        const Texture& tex = *t.value();
        EXPECT_GE(tex.width(), 1) << input;
        EXPECT_LE(static_cast<std::size_t>(tex.width()) * static_cast<std::size_t>(tex.height()), limits.max_pixels) << input;
        const Vec4 c = tex.sample({0.3f, 0.7f}, {0.01f, 0}, {0, 0.01f}, Sampler{});
        for (float v : {c.x, c.y, c.z, c.w}) EXPECT_TRUE(v >= 0 && v <= 1) << input;
    }
}

// fuzz/load_model_fuzzer: a PLY header whose end_header is followed by something other than a
// line end, or does not start a line, made assimp 5.2.5's PLY reader run past its buffer
// (SIGBUS/SIGSEGV) or loop forever. load_model now refuses such a header before assimp sees it.
TEST(Regression, PlyEndHeaderWithoutALineEndIsRefusedBeforeAssimp) {
    const fs::path dir = facet_test::test_temp_dir("facet_regression");
    for (const std::string& tail : {std::string("end_header\x0b" "0", 12), std::string("end_header0 0 0\n"),
                                    std::string("end_header", 10)}) {
        const std::string path = (dir / "bad.ply").string();
        write_bytes(path, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" + tail);
        const auto r = load_model(path);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().code, ErrorCode::bad_format);
        EXPECT_TRUE(mentions(r.error().message, "end_header is not followed by a line end")) << r.error().message;
    }
    // Nor one in the middle of a line (assimp looped forever, or read past its buffer).
    const std::string mid = (dir / "mid.ply").string();
    write_bytes(mid, "ply\nformat ascii 1.0\nelement vertex 0\ncomment xxend_header\n");
    const auto m = load_model(mid);
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().code, ErrorCode::bad_format);
    EXPECT_TRUE(mentions(m.error().message, "no end_header line")) << m.error().message;
    // CRLF headers are fine.
    const std::string crlf = (dir / "crlf.ply").string();
    write_bytes(crlf, "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                      "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                      "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n");
    const auto ok = load_model(crlf);
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->scene.triangle_count(), 1u);
}

// fuzz/load_model_fuzzer: a PLY property of a type PLY does not have ("uint4") made assimp 5.2.5
// loop forever (a timeout). load_model refuses unknown types, in lists too, before assimp reads.
TEST(Regression, PlyPropertyOfAnUnknownTypeIsRefusedBeforeAssimp) {
    const fs::path dir = facet_test::test_temp_dir("facet_regression");
    for (const std::string& property : {std::string("property uint4 x"), std::string("property list uint4 int vertex_index"),
                                        std::string("property list uchar quad vertex_index")}) {
        const std::string path = (dir / "bad.ply").string();
        write_bytes(path, "ply\nformat ascii 1.0\nelement vertex 3\n" + property + "\nend_header\n0\n1\n2\n");
        const auto r = load_model(path);
        ASSERT_FALSE(r.ok()) << property;
        EXPECT_EQ(r.error().code, ErrorCode::bad_format);
        EXPECT_TRUE(mentions(r.error().message, "unknown")) << r.error().message;
    }
}

// Comparing facet's PLY reader with assimp on generated headers: a comment among an element's
// properties makes assimp 5.2.5 end the property list there and read the rest wrongly (an error,
// garbled positions, or a minute of work on a 300-byte binary file). load_model refuses such a
// header with a message naming the element; a comment before the first element or after the last
// property of one is still read.
TEST(Regression, PlyCommentAmongPropertiesIsRefusedBeforeAssimp) {
    const fs::path dir = facet_test::test_temp_dir("facet_regression");
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (const std::string& properties : {std::string("comment c\nproperty float x\nproperty float y\nproperty float z\n"),
                                          std::string("property float x\nobj_info o\nproperty float y\nproperty float z\n")}) {
        const std::string path = (dir / "comment.ply").string();
        write_bytes(path, "ply\nformat ascii 1.0\nelement vertex 3\n" + properties + faces);
        const auto r = load_model(path);
        ASSERT_FALSE(r.ok()) << properties;
        EXPECT_EQ(r.error().code, ErrorCode::bad_format);
        EXPECT_TRUE(mentions(r.error().message, "comment among the properties of element 'vertex'")) << r.error().message;
    }
    const std::string fine = (dir / "fine.ply").string();
    write_bytes(fine, "ply\nformat ascii 1.0\ncomment a\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "comment b\n" + faces);
    const auto ok = load_model(fine);
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(ok->scene.triangle_count(), 1u);
}

// assimp's MDL reader hands over a skin of height 0 as a "compressed" texture of 65,538 bytes with
// no format hint, in a buffer it allocated empty; reading it ran off the buffer's end (the CI fuzz
// run, AddressSanitizer). The input, reduced from the fuzzer's: a 3D GameStudio MDL5 header for 3
// vertices and 1 triangle, one such skin and the triangle. The model loads; the texture is refused.
TEST(Regression, MdlSkinOfHeightZeroIsNotReadAsACompressedTexture) {
    const fs::path input = k_regression_dir / "load_model" / "mdl_skin_of_height_zero.mdl";
    const auto r = load_model(input.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->scene.triangle_count(), 1u);
    for (const SceneObject& o : r->scene.objects) EXPECT_EQ(o.material.base_colour_texture, nullptr);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_TRUE(mentions(r->warnings[0], input.string()) && mentions(r->warnings[0], "embedded texture") &&
                mentions(r->warnings[0], "without a format hint"))
        << r->warnings[0];
}

// Every saved load_model_fuzzer input that facet now guards against, loaded as the fuzzer loads
// it (the file's extension is its format): an Error or a scene, never a crash or an exception.
TEST(Regression, LoadModelFuzzerInputsLoadOrFailCleanly) {
    const std::vector<fs::path> inputs = inputs_of("load_model");
    ASSERT_FALSE(inputs.empty());
    LoadOptions options;
    options.max_triangles = 200'000;
    options.texture_limits = {.max_size = 512, .max_pixels = 256 * 256};
    for (const fs::path& input : inputs) {
        const auto r = load_model(input.string(), options);
        if (!r.ok()) {
            EXPECT_NE(r.error().code, ErrorCode::invalid_argument) << input;
            EXPECT_TRUE(mentions(r.error().message, input.string())) << r.error().message;
            continue;
        }
        EXPECT_GT(r->scene.triangle_count(), 0u) << input;
    }
}

}  // namespace
