// Property: DrawState::clear draws exactly what Framebuffer::clear followed by the same draw draws,
// colour and depth, byte for byte: over the whole target even when the viewport is smaller, with
// several batches, for both drawing orders (visible-only and one pass with blending), for a draw
// with no triangles and one whose depth test passes nothing, on 1 and 3 threads and several tiles,
// and on a target whose empty tiles are cleared between the kernels' work (DeferredFills). A draw
// that does not keep its depth (DrawState::keep_depth) draws the same colour and leaves the depth
// of the target's empty tiles alone.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "facet/renderer.hpp"

namespace {

using namespace facet;

struct ColourShader {
    static constexpr int k_varyings = 3;
    const std::vector<Vec4>* pos;
    const std::vector<Vec3>* colour;
    Vec4 vertex(std::uint32_t i, Varyings<3>& out) const {
        out.set(0, (*colour)[i]);
        return (*pos)[i];
    }
    Vec4 fragment(const FragmentIn<3>& in) const { return Vec4(in.v.vec3(0), 0.6f); }
};

struct Triangles {
    std::vector<Vec4> pos;
    std::vector<Vec3> colour;
};

// Triangles with corners in [lo, hi] in x and y (clip space, w = 1).
Triangles random_triangles(int count, float lo = -1.2f, float hi = 1.2f) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(lo, hi), unit(0.0f, 1.0f);
    Triangles t;
    for (int i = 0; i < count * 3; ++i) {
        t.pos.push_back(Vec4{u(rng), u(rng), unit(rng), 1.0f});
        t.colour.push_back(Vec3{unit(rng), unit(rng), unit(rng)});
    }
    return t;
}

struct Output {
    std::vector<Rgba8> colour;
    std::vector<float> depth;
};

struct Size {
    int width, height;
};

Output draw(const Triangles& tris, DrawState state, RendererConfig config, bool clear_in_draw, Size size = {150, 110}) {
    Framebuffer fb(size.width, size.height);
    fb.clear(Vec4{0.9f, 0.1f, 0.5f, 1.0f}, 0.25f);  // what a clear must replace everywhere
    const ClearValues clear{Vec4{0.2f, 0.3f, 0.4f, 1.0f}, 0.8f};
    if (clear_in_draw)
        state.clear = clear;
    else
        fb.clear(clear.colour, clear.depth);
    Renderer renderer(config);
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(tris.pos.size()), {}},
                  ColourShader{&tris.pos, &tris.colour});
    const std::size_t n = static_cast<std::size_t>(size.width) * static_cast<std::size_t>(size.height);
    return {{fb.colour_data(), fb.colour_data() + n}, {fb.depth_data(), fb.depth_data() + n}};
}

bool same(const Output& a, const Output& b) {
    return a.colour == b.colour && std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

TEST(DrawClear, EqualsFramebufferClearThenDraw) {
    const Triangles tris = random_triangles(400);
    const Triangles none;
    for (Blend blend : {Blend::none, Blend::alpha})
        for (DepthTest test : {DepthTest::less, DepthTest::never})
            for (bool small_viewport : {false, true})
                for (int threads : {1, 3})
                    for (int tile : {8, 64}) {
                        DrawState state;
                        state.cull = CullMode::none;
                        state.blend = blend;
                        state.depth_test = test;
                        if (small_viewport) state.viewport = Rect{20, 10, 90, 70};
                        const RendererConfig config{.threads = threads, .tile_size = tile, .batch_triangles = 150};
                        for (const Triangles* t : {&tris, &none}) {
                            const Output expected = draw(*t, state, config, false);
                            EXPECT_TRUE(same(draw(*t, state, config, true), expected))
                                << "blend " << static_cast<int>(blend) << ", test " << static_cast<int>(test)
                                << ", small viewport " << small_viewport << ", threads " << threads << ", tile "
                                << tile << ", triangles " << t->pos.size() / 3;
                        }
                    }
    // The comparison is not vacuous: the clear values (outside the viewport) and the triangles show.
    DrawState state;
    state.cull = CullMode::none;
    state.viewport = Rect{20, 10, 90, 70};
    const Output out = draw(tris, state, {.threads = 1}, true);
    int cleared = 0, drawn = 0;
    for (std::size_t i = 0; i < out.depth.size(); ++i) (out.depth[i] == 0.8f ? cleared : drawn)++;
    EXPECT_GT(cleared, 100);
    EXPECT_GT(drawn, 1000);
}

// Tiles that no triangle reaches are cleared between the kernels' work (DeferredFills) when every
// row of them is whole aligned cache lines: a target 16-pixel aligned, with triangles in one corner
// so that most tiles are empty, and batches so small that every batch's fills must be done before
// the next batch reads the target.
TEST(DrawClear, EmptyTilesAreClearedWhereverTheTrianglesAre) {
    const Triangles corner = random_triangles(300, -0.95f, -0.2f);
    const Triangles spread = random_triangles(300);
    const Size size{256, 192};
    for (DepthTest test : {DepthTest::less, DepthTest::lequal})
        for (int threads : {1, 2, 3})
            for (int tile : {16, 32, 64})
                for (int batch : {0, 40})
                    for (const Triangles* t : {&corner, &spread}) {
                        DrawState state;
                        state.cull = CullMode::none;
                        state.depth_test = test;
                        const RendererConfig config{.threads = threads, .tile_size = tile, .batch_triangles = batch};
                        EXPECT_TRUE(same(draw(*t, state, config, true, size), draw(*t, state, config, false, size)))
                            << "test " << static_cast<int>(test) << ", threads " << threads << ", tile " << tile
                            << ", batch " << batch << ", triangles in the corner " << (t == &corner);
                    }
    // Most of the target is empty tiles, and the triangles show.
    DrawState state;
    state.cull = CullMode::none;
    const Output out = draw(corner, state, {.threads = 1}, true, size);
    int cleared = 0, drawn = 0;
    for (std::size_t i = 0; i < out.depth.size(); ++i) (out.depth[i] == 0.8f ? cleared : drawn)++;
    EXPECT_GT(cleared, size.width * size.height / 2);
    EXPECT_GT(drawn, 1000);
}

// The "don't care" depth store: the same colour as a draw that stores its depth, in both orders,
// with one batch or several (all but the last store theirs: the next one reads it); and with one
// batch in the visible-only order, the empty tiles' depth is not written at all.
TEST(DrawClear, DrawThatKeepsNoDepthDrawsTheSameColour) {
    const Triangles corner = random_triangles(300, -0.95f, -0.2f);
    const Triangles spread = random_triangles(300);
    const Size size{256, 192};
    for (Blend blend : {Blend::none, Blend::alpha})
        for (int threads : {1, 3})
            for (int tile : {16, 64})
                for (int batch : {0, 40})
                    for (const Triangles* t : {&corner, &spread}) {
                        DrawState state;
                        state.cull = CullMode::none;
                        state.blend = blend;
                        const RendererConfig config{.threads = threads, .tile_size = tile, .batch_triangles = batch};
                        const Output kept = draw(*t, state, config, true, size);
                        state.keep_depth = false;
                        EXPECT_EQ(draw(*t, state, config, true, size).colour, kept.colour)
                            << "blend " << static_cast<int>(blend) << ", threads " << threads << ", tile " << tile
                            << ", batch " << batch << ", triangles in the corner " << (t == &corner);
                    }
    DrawState state;
    state.cull = CullMode::none;
    state.keep_depth = false;
    const Output out = draw(corner, state, {.threads = 2}, true, size);
    int untouched = 0;
    for (const float d : out.depth) untouched += d == 0.25f;  // the value before the draw's clear
    EXPECT_GT(untouched, size.width * size.height / 2);
    state.keep_depth = true;
    for (const float d : draw(corner, state, {.threads = 2}, true, size).depth) ASSERT_NE(d, 0.25f);
}

}  // namespace
