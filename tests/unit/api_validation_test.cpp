// The library validates its inputs at the boundary (docs/architecture.md, "Errors"): misuse throws
// FacetError with ErrorCode::invalid_argument, bad geometry is dropped and counted in DrawStats,
// fallible I/O returns an Error. One test per kind of bad input, each asserting the documented
// outcome (docs/RELIABILITY.md lists them).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "facet/io.hpp"
#include "facet/mesh.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "facet/texture.hpp"

namespace {

using namespace facet;

// Runs `f` and returns the ErrorCode of the FacetError it throws; fails the test if it throws
// nothing or something else.
template <class F>
ErrorCode code_thrown_by(F&& f) {
    try {
        f();
    } catch (const FacetError& e) {
        EXPECT_FALSE(e.error().message.empty());
        EXPECT_STREQ(e.what(), e.error().message.c_str());
        return e.error().code;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw something other than FacetError: " << e.what();
        return ErrorCode::io;
    }
    ADD_FAILURE() << "did not throw";
    return ErrorCode::io;
}

// A full-screen-ish triangle, counting how often each vertex is asked for.
struct CountingShader {
    static constexpr int k_varyings = 1;
    std::vector<std::atomic<int>>* calls;
    std::uint32_t vertices_available;
    Vec4 vertex(std::uint32_t i, Varyings<1>& out) const {
        if (i >= vertices_available) {
            ADD_FAILURE() << "vertex " << i << " asked for, only " << vertices_available << " exist";
            return {0, 0, 0, 1};
        }
        (*calls)[i]++;
        out[0] = 1;
        static const Vec4 corners[3] = {{-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1}, {-1, 3, 0.5f, 1}};
        return corners[i % 3];
    }
    Vec4 fragment(const FragmentIn<1>&) const { return {1, 1, 1, 1}; }
};

struct Fixture {
    std::vector<std::atomic<int>> calls;
    CountingShader shader;
    explicit Fixture(std::uint32_t n) : calls(n), shader{&calls, n} {}
};

std::size_t white_pixels(const Framebuffer& fb) {
    std::size_t n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) n += fb.colour(x, y).r == 255;
    return n;
}

// ---- Framebuffer and Renderer configuration ---------------------------------------------------

TEST(ApiValidation, FramebufferSizesOutsideTheRangeThrowInvalidArgument) {
    for (auto [w, h] : {std::pair{0, 1}, {1, 0}, {-1, 5}, {5, -1}, {k_max_target_size + 1, 1}, {1, k_max_target_size + 1},
                        {std::numeric_limits<int>::min(), 1}, {std::numeric_limits<int>::max(), 1}})
        EXPECT_EQ(code_thrown_by([&] { Framebuffer{w, h}; }), ErrorCode::invalid_argument) << w << "x" << h;
    for (auto [w, h] : {std::pair{0, 1}, {1, k_max_target_size + 1}}) {
        Rgba8 pixel;
        EXPECT_EQ(code_thrown_by([&] { Framebuffer(w, h, &pixel); }), ErrorCode::invalid_argument) << w << "x" << h;
    }
    EXPECT_NO_THROW(Framebuffer(1, 1));
    EXPECT_NO_THROW(Framebuffer(k_max_target_size, 1));
}

TEST(ApiValidation, RendererTileSizeMustBeAPowerOfTwoFrom8To64) {
    for (int t : {0, -8, 1, 4, 7, 12, 48, 96, 128, 1 << 30})
        EXPECT_EQ(code_thrown_by([&] { Renderer{{.threads = 1, .tile_size = t}}; }), ErrorCode::invalid_argument) << t;
    for (int t : {8, 16, 32, 64}) EXPECT_EQ(Renderer({.threads = 1, .tile_size = t}).tile_size(), t);
}

TEST(ApiValidation, RendererBatchSizeMustNotBeNegative) {
    for (int b : {-1, -1000})
        EXPECT_EQ(code_thrown_by([&] { Renderer{{.threads = 1, .batch_triangles = b}}; }), ErrorCode::invalid_argument) << b;
    for (int b : {0, 1, 5000}) EXPECT_NO_THROW(Renderer({.threads = 1, .batch_triangles = b})) << b;
}

TEST(ApiValidation, NonPositiveThreadCountsMeanOnePerCore) {
    for (int n : {0, -1, -100}) EXPECT_GE(Renderer({.threads = n}).threads(), 1) << n;
}

// ---- draw: viewport ----------------------------------------------------------------------------

TEST(ApiValidation, InvalidViewportsThrowAndDrawNothing) {
    Renderer r({.threads = 2, .tile_size = 8});
    Framebuffer fb(32, 32);
    Fixture f(3);
    for (Rect vp : {Rect{0, 0, 0, 10}, Rect{0, 0, 10, 0}, Rect{0, 0, -1, -1}, Rect{-1, 0, 8, 8}, Rect{0, -1, 8, 8},
                    Rect{k_max_target_size - 4, 0, 8, 8}, Rect{0, 0, k_max_target_size + 1, 8}}) {
        fb.clear({0, 0, 0, 1});
        DrawState state;
        state.viewport = vp;
        EXPECT_EQ(code_thrown_by([&] { r.draw(fb, state, DrawInput{3, {}}, f.shader); }), ErrorCode::invalid_argument)
            << vp.x << "," << vp.y << " " << vp.width << "x" << vp.height;
        EXPECT_EQ(white_pixels(fb), 0u);
    }
}

TEST(ApiValidation, ViewportsReachingPastTheTargetAreClippedToIt) {
    Renderer r({.threads = 2, .tile_size = 8});
    Framebuffer fb(32, 32);
    Fixture f(3);
    DrawState state;
    state.cull = CullMode::none;
    // Partly off the target: only the part on it is drawn.
    fb.clear({0, 0, 0, 1});
    state.viewport = {24, 28, 100, 100};
    r.draw(fb, state, DrawInput{3, {}}, f.shader);
    EXPECT_EQ(white_pixels(fb), 8u * 4u);
    // Wholly off the target (but within the limits): nothing, and no crash.
    fb.clear({0, 0, 0, 1});
    state.viewport = {40, 40, 16, 16};
    const DrawStats s = r.draw(fb, state, DrawInput{3, {}}, f.shader);
    EXPECT_EQ(white_pixels(fb), 0u);
    EXPECT_EQ(s.triangles_in, 1u);
}

// ---- draw: vertex and index input --------------------------------------------------------------

TEST(ApiValidation, NoVerticesAndNoIndicesDrawNothingAndCallNoShader) {
    Renderer r({.threads = 2});
    Framebuffer fb(16, 16);
    fb.clear({0, 0, 0, 1});
    Fixture f(0);
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{0, {}}, f.shader);
    EXPECT_EQ(s.triangles_in, 0u);
    EXPECT_EQ(s.triangles_rasterized, 0u);
    EXPECT_EQ(white_pixels(fb), 0u);
}

TEST(ApiValidation, ANullIndexSpanMeansConsecutiveTriples) {
    Renderer r({.threads = 1});
    Framebuffer fb(16, 16);
    fb.clear({0, 0, 0, 1});
    Fixture f(3);
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{3, std::span<const std::uint32_t>(static_cast<const std::uint32_t*>(nullptr), std::size_t{0})}, f.shader);
    EXPECT_EQ(s.triangles_in, 1u);
    EXPECT_EQ(s.triangles_rasterized, 1u);
    EXPECT_EQ(white_pixels(fb), 16u * 16u);
}

TEST(ApiValidation, IndicesWithZeroVerticesAreAllDroppedAndCounted) {
    Renderer r({.threads = 2});
    Framebuffer fb(16, 16);
    fb.clear({0, 0, 0, 1});
    Fixture f(0);
    const std::uint32_t idx[] = {0, 1, 2, 0, 0, 0};
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{0, idx}, f.shader);
    EXPECT_EQ(s.triangles_in, 2u);
    EXPECT_EQ(s.triangles_invalid, 2u);
    EXPECT_EQ(s.triangles_rasterized, 0u);
    EXPECT_EQ(white_pixels(fb), 0u);
}

TEST(ApiValidation, OutOfRangeIndicesDropOnlyTheirTriangles) {
    Renderer r({.threads = 2});
    Framebuffer fb(16, 16);
    fb.clear({0, 0, 0, 1});
    Fixture f(3);
    const std::uint32_t max = std::numeric_limits<std::uint32_t>::max();
    // vertex_count itself, the largest index, one past the largest, and one good triangle.
    const std::uint32_t idx[] = {0, 1, 3, max, 1, 2, 0, max - 1, 2, 0, 1, 2};
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{3, idx}, f.shader);
    EXPECT_EQ(s.triangles_in, 4u);
    EXPECT_EQ(s.triangles_invalid, 3u);
    EXPECT_EQ(s.triangles_rasterized, 1u);
    EXPECT_EQ(white_pixels(fb), 16u * 16u);
}

TEST(ApiValidation, ATrailingPartialTriangleIsIgnored) {
    Renderer r({.threads = 1});
    Framebuffer fb(8, 8);
    Fixture f(5);
    EXPECT_EQ(r.draw(fb, DrawState{}, DrawInput{5, {}}, f.shader).triangles_in, 1u);  // vertices 3 and 4 left over
    const std::uint32_t idx[] = {0, 1, 2, 2, 1};
    EXPECT_EQ(r.draw(fb, DrawState{}, DrawInput{5, idx}, f.shader).triangles_in, 1u);
}

// The vertex stage asks for exactly the vertices [0, vertex_count), each once, whatever the
// indices say and however many threads run it: a shader whose arrays hold vertex_count entries is
// never asked to read past them, even when indices point further.
TEST(ApiValidation, EachVertexBelowVertexCountIsShadedOnceAndNoneBeyond) {
    for (int threads : {1, 3}) {
        Renderer r({.threads = threads});
        Framebuffer fb(16, 16);
        const std::uint32_t n = 3 * 4096 + 7;  // several blocks of the vertex stage
        Fixture f(n);
        std::vector<std::uint32_t> idx = {0, 1, 2, n, n + 1, n + 2, n - 1, n - 2, n - 3};
        const DrawStats s = r.draw(fb, DrawState{}, DrawInput{n, idx}, f.shader);
        EXPECT_EQ(s.triangles_invalid, 1u);
        for (std::uint32_t i = 0; i < n; ++i) ASSERT_EQ(f.calls[i].load(), 1) << "vertex " << i << ", " << threads << " threads";
    }
}

TEST(ApiValidation, NonFinitePositionsDropOnlyTheirTriangles) {
    Renderer r({.threads = 1});
    Framebuffer fb(16, 16);
    fb.clear({0, 0, 0, 1});
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const Vec4 pos[] = {{-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1}, {-1, 3, 0.5f, 1}, {nan, 0, 0.5f, 1}, {0, inf, 0.5f, 1}, {0, 0, 0.5f, nan}};
    const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    const std::uint32_t idx[] = {0, 1, 3, 0, 4, 2, 5, 1, 2, 0, 1, 2};
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{6, idx}, shader);
    EXPECT_EQ(s.triangles_invalid, 3u);
    EXPECT_EQ(s.triangles_rasterized, 1u);
    EXPECT_EQ(white_pixels(fb), 16u * 16u);
}

// ---- scenes, meshes, textures, images ----------------------------------------------------------

TEST(ApiValidation, MeshValidateNamesEachMismatch) {
    Mesh m = make_cube();
    ASSERT_TRUE(m.validate().ok());
    auto expect_error = [](const Mesh& bad, const char* words) {
        const Status s = bad.validate();
        ASSERT_FALSE(s.ok()) << words;
        EXPECT_EQ(s.error().code, ErrorCode::invalid_argument);
        EXPECT_NE(s.error().message.find(words), std::string::npos) << s.error().message;
    };
    Mesh a = m;
    a.normals.pop_back();
    expect_error(a, "normals");
    Mesh b = m;
    b.colours.push_back({1, 1, 1, 1});
    expect_error(b, "colours");
    Mesh c = m;
    c.uvs.resize(1);
    expect_error(c, "uvs");
    Mesh d = m;
    d.indices.push_back(0);
    expect_error(d, "multiple of 3");
    Mesh e = m;
    e.indices[4] = static_cast<std::uint32_t>(e.positions.size());
    expect_error(e, "out of range");
}

// Shaders read attributes at every vertex index: render_scene refuses an object whose arrays do
// not match its positions instead of reading past them.
TEST(ApiValidation, RenderSceneRefusesObjectsWithMismatchedAttributeArrays) {
    Renderer r({.threads = 1});
    Framebuffer fb(16, 16);
    for (int which = 0; which < 3; ++which) {
        Scene scene;
        scene.objects.push_back({make_cube(), Mat4::identity(), {}});
        Mesh& m = scene.objects[0].mesh;
        if (which == 0) m.normals.resize(2);
        if (which == 1) m.colours.resize(3);
        if (which == 2) m.uvs.resize(1);
        const Camera camera = frame_scene(scene, 0.3f, 0.2f, radians(45.0f), 1.0f);
        for (Shading shading : {Shading::lit, Shading::vertex_color, Shading::texture}) {
            RenderSettings settings;
            settings.shading = shading;
            EXPECT_EQ(code_thrown_by([&] { render_scene(r, fb, scene, camera, settings); }), ErrorCode::invalid_argument)
                << which;
        }
    }
}

TEST(ApiValidation, ResolveSupersampledNeedsAFactorThatDividesTheSource) {
    Framebuffer fb(12, 8);
    Image colour;
    std::vector<float> depth;
    for (int factor : {0, -1, -2, 3, 5, 16})
        EXPECT_EQ(code_thrown_by([&] { resolve_supersampled(fb, factor, colour, &depth); }), ErrorCode::invalid_argument)
            << factor;
    resolve_supersampled(fb, 4, colour, &depth);
    EXPECT_EQ(colour.width, 3);
    EXPECT_EQ(colour.height, 2);
    EXPECT_EQ(depth.size(), 6u);
}

TEST(ApiValidation, TextureFromAMismatchedImageThrows) {
    EXPECT_EQ(code_thrown_by([] { Texture t(Image{2, 2, std::vector<Rgba8>(3)}); }), ErrorCode::invalid_argument);
    EXPECT_EQ(code_thrown_by([] { Texture t(Image{0, 0, {}}); }), ErrorCode::invalid_argument);
    EXPECT_EQ(code_thrown_by([] { Texture t(Image{-2, -2, std::vector<Rgba8>(4)}); }), ErrorCode::invalid_argument);
}

TEST(ApiValidation, DecodingNoBytesIsABadFormatError) {
    const unsigned char one = 0x89;
    for (auto [bytes, size] : {std::pair<const void*, std::size_t>{nullptr, 0}, {nullptr, 100}, {&one, 0}, {&one, 1}}) {
        auto t = Texture::decode(bytes, size, "memory");
        ASSERT_FALSE(t.ok());
        EXPECT_EQ(t.error().code, ErrorCode::bad_format);
        EXPECT_NE(t.error().message.find("memory"), std::string::npos);
    }
}

TEST(ApiValidation, WritingMismatchedImagesIsInvalidArgumentAndWritesNothing) {
    const std::string path = ::testing::TempDir() + "facet_api_validation_never_written.png";
    std::remove(path.c_str());
    for (const Image& bad : {Image{2, 2, std::vector<Rgba8>(3)}, Image{0, 0, {}}, Image{-1, 4, {}}}) {
        const Status s = write_png(path, bad);
        ASSERT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, ErrorCode::invalid_argument);
    }
    const Status g = write_png_gray16(path, 3, 3, std::vector<std::uint16_t>(8));
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.error().code, ErrorCode::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
