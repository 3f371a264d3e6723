// Property: the SIMD kernel of anti-aliased lines (src/shade/line_aa_simd.cpp, CompiledLineAaPass)
// draws the bytes of its specification, shade_tile with LineAaCoverage (the "scalar" ISA), on every
// ISA, for the shaders render_scene draws lines with (LambertBaseColour, VertexColour).
// Adversarial for the kernel: a target of random colours whose depths are those of surfaces drawn
// before, half of them at exactly the depth of half the lines (ties: every depth test passes some
// pixels and fails others); segments of every direction, lengths from under a pixel to across
// several tiles, widths 1, 2.5 and 3, lists (free ends, which fade) and strips (mitred joins, which
// do not) and a loop; vertex colours whose alpha is outside [0, 1], -0 or NaN, and whose channels are
// NaN or infinite; normals that are zero or tiny (the lanes leave those to the specification); a
// base colour with alpha < 1 and a grey one; tiles of 8 to 64 pixels (vectors cut by tile edges).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "facet/isa.hpp"
#include "facet/renderer.hpp"
#include "facet/shaders.hpp"
#include "support/pixels.hpp"

namespace {

using namespace facet;

constexpr int k_width = 157, k_height = 101;
constexpr float k_nan = std::numeric_limits<float>::quiet_NaN(), k_inf = std::numeric_limits<float>::infinity();
constexpr float k_tie_z = 0.25f;  // clip z (w = 1) of half the surfaces and half the lines

// Lines in clip space (the uniforms' clip_from_object is the identity, w = 1), with colours and
// normals; the indices of a list, then of a strip and a loop.
struct LineSet {
    Mesh mesh;
    std::vector<std::uint32_t> list, strip;
};

LineSet random_lines(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.1f, 1.1f), unit(0.0f, 1.0f), angle(0.0f, 6.2831853f);
    LineSet s;
    Mesh& m = s.mesh;
    auto vertex = [&](Vec3 p, int i) {
        m.positions.push_back(p);
        Vec3 n{unit(rng) - 0.5f, unit(rng) - 0.5f, 1.0f};
        if (i / 2 % 37 == 0) n = {0, 0, 0};  // both ends of a segment of the list
        if (i / 2 % 41 == 0) n = {1e-30f, 0, 1e-30f};
        m.normals.push_back(n);
        Vec4 c{unit(rng), unit(rng), unit(rng), unit(rng) * 1.4f - 0.2f};
        if (i % 29 == 0) c.w = -0.0f;
        if (i % 31 == 0) c.w = k_nan;
        if (i % 43 == 0) c.x = k_nan;
        if (i % 47 == 0) c.y = k_inf;
        m.colours.push_back(c);
    };
    int i = 0;
    for (int k = 0; k < 300; ++k, i += 2) {  // a list: lengths from 0.01 to ~0.6 of the target
        const float z = k % 2 ? k_tie_z : unit(rng) * 1.2f - 0.1f;
        const Vec3 a{u(rng), u(rng), z};
        const float length = k % 5 == 0 ? 0.01f * unit(rng) : 0.3f * unit(rng), t = angle(rng);
        vertex(a, i);
        vertex({a.x + length * std::cos(t), a.y + length * std::sin(t), k % 3 ? z : z + 0.1f * unit(rng)}, i + 1);
        s.list.insert(s.list.end(), {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1)});
    }
    const int first = i;  // a strip, then a loop (its last vertex is its first)
    for (int k = 0; k < 60; ++k, ++i) vertex({u(rng) * 0.8f, u(rng) * 0.8f, k % 2 ? k_tie_z : 0.5f * unit(rng)}, i);
    for (int k = first; k + 1 < i; ++k) s.strip.insert(s.strip.end(), {static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(k + 1)});
    const int loop = i;
    for (int k = 0; k < 12; ++k, ++i) {
        const float t = 6.2831853f * static_cast<float>(k) / 12;
        vertex({0.5f * std::cos(t), 0.4f * std::sin(t), k_tie_z}, i);
    }
    for (int k = 0; k < 12; ++k)
        s.strip.insert(s.strip.end(), {static_cast<std::uint32_t>(loop + k), static_cast<std::uint32_t>(loop + (k + 1) % 12)});
    return s;
}

// Random colours, and depths of triangles drawn with DepthTest::always (1 elsewhere), half of them
// at k_tie_z.
void fill_target(Framebuffer& fb) {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f), unit(0.0f, 1.0f);
    for (int i = 0; i < k_width * k_height; ++i) {
        fb.colour_data()[i] = {static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                               static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng))};
        fb.depth_data()[i] = 1.0f;
    }
    Mesh surfaces;
    for (int t = 0; t < 40; ++t) {
        const float z = t % 2 ? k_tie_z : unit(rng) * 1.2f - 0.1f;
        const Vec3 c{u(rng), u(rng), z};
        for (int k = 0; k < 3; ++k) {
            surfaces.positions.push_back(c + Vec3{u(rng) * 0.4f, u(rng) * 0.4f, t % 2 ? 0.0f : 0.2f * unit(rng)});
            surfaces.indices.push_back(static_cast<std::uint32_t>(t * 3 + k));
        }
    }
    ShadingUniforms u0;
    u0.clip_from_object = Mat4::identity();
    Renderer renderer({.threads = 1});
    DrawState state;
    state.cull = CullMode::none;
    state.depth_test = DepthTest::always;
    const std::vector<Rgba8> colours(fb.colour_data(), fb.colour_data() + k_width * k_height);
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(surfaces.positions.size()), surfaces.indices},
                  shaders::Mask{MeshArrays::of(surfaces), u0});
    std::copy(colours.begin(), colours.end(), fb.colour_data());
}

template <class S>
std::vector<Rgba8> draw(const LineSet& lines, const S& shader, DepthTest test, int tile) {
    Renderer renderer({.threads = 2, .tile_size = tile});
    Framebuffer fb(k_width, k_height);
    fill_target(fb);
    DrawState state;
    state.depth_test = test;
    const auto n = static_cast<std::uint32_t>(lines.mesh.positions.size());
    renderer.draw(fb, state, {n, lines.list, Topology::lines, {.line_width = 1, .line_aa = true}}, shader);
    renderer.draw(fb, state, {n, lines.list, Topology::lines, {.line_width = 2.5f, .line_aa = true}}, shader);
    renderer.draw(fb, state, {n, lines.strip, Topology::lines, {.line_width = 3, .line_aa = true}}, shader);
    return {fb.colour_data(), fb.colour_data() + k_width * k_height};
}

int differing_pixels(const std::vector<Rgba8>& a, const std::vector<Rgba8>& b) {
    int n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i], &b[i], sizeof(Rgba8)) != 0;
    return n;
}

template <class S>
void expect_same_bytes_on_every_isa(const LineSet& lines, const S& shader, const char* name) {
    const struct {
        DepthTest test;
        int tile;
    } cases[] = {{DepthTest::less, 64}, {DepthTest::lequal, 8}, {DepthTest::equal, 64}, {DepthTest::greater, 8}, {DepthTest::always, 16}};
    for (const auto [test, tile] : cases) {
        ASSERT_TRUE(select_isa("scalar"));
        const std::vector<Rgba8> reference = draw(lines, shader, test, tile);
        for (const std::string& isa : available_isas()) {
            if (isa == "scalar") continue;
            ASSERT_TRUE(select_isa(isa));
            EXPECT_EQ(differing_pixels(draw(lines, shader, test, tile), reference), 0)
                << name << " on " << isa << ", depth test " << static_cast<int>(test) << ", tiles " << tile;
        }
    }
}

ShadingUniforms uniforms(Vec4 base_colour) {
    ShadingUniforms u;
    u.clip_from_object = Mat4::identity();
    u.base_colour = base_colour;
    u.key = {{0.3f, 0.5f, 0.8f}, {1, 1, 1}};
    return u;
}

TEST(LineAaKernel, VertexColourDrawsTheSpecificationsBytesOnEveryIsa) {
    facet_test::IsaGuard guard;
    const LineSet lines = random_lines(3);
    expect_same_bytes_on_every_isa(lines, shaders::VertexColour{MeshArrays::of(lines.mesh), uniforms({1, 1, 1, 1})}, "VertexColour");
}

TEST(LineAaKernel, LambertBaseColourDrawsTheSpecificationsBytesOnEveryIsa) {
    facet_test::IsaGuard guard;
    const LineSet lines = random_lines(3);
    MeshArrays arrays = MeshArrays::of(lines.mesh);
    arrays.colours = nullptr;
    // The lambert mode's grey colour under a white key light, and a colour with alpha < 1 under a
    // coloured key and fill.
    expect_same_bytes_on_every_isa(lines, shaders::LambertBaseColour{arrays, uniforms({0.8f, 0.8f, 0.8f, 1})}, "lambert mode");
    ShadingUniforms u = uniforms({0.9f, 0.4f, 0.2f, 0.6f});
    u.key.colour = {1.0f, 0.7f, 0.5f};
    u.fill = {{-0.5f, 0.2f, 0.4f}, {0.2f, 0.3f, 0.4f}};
    expect_same_bytes_on_every_isa(lines, shaders::LambertBaseColour{arrays, u}, "coloured lights");
}

// The draws above meet ties: the lines at k_tie_z pass the equal test over the surfaces there, and
// the others draw where always passes.
TEST(LineAaKernel, TheDrawsMeetTiesAndOtherDepths) {
    const LineSet lines = random_lines(3);
    const shaders::VertexColour shader{MeshArrays::of(lines.mesh), uniforms({1, 1, 1, 1})};
    Framebuffer before(k_width, k_height);
    fill_target(before);
    const std::vector<Rgba8> base(before.colour_data(), before.colour_data() + k_width * k_height);
    const int equal = differing_pixels(draw(lines, shader, DepthTest::equal, 64), base);
    const int all = differing_pixels(draw(lines, shader, DepthTest::always, 64), base);
    EXPECT_GT(equal, 100);        // ties pass the equal test (304 pixels)
    EXPECT_GT(all, equal + 500);  // and fail elsewhere (9,506 drawn with always)
}

}  // namespace
