// Property: output is identical byte for byte whatever the thread count or tile size (the renderer's
// documented guarantee). A scene of thousands of random overlapping triangles, with depth test less,
// coplanar duplicates whose order decides the winner, perspective (random w), clipped triangles,
// derivatives, and a second blended draw, rendered with threads 1, 2, 3, 8 and tile sizes 8, 16, 32, 64:
// every colour byte and every depth bit equal.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "facet/isa.hpp"
#include "facet/renderer.hpp"
#include "support/pixels.hpp"

namespace {

using namespace facet;

struct Scene {
    std::vector<Vec4> pos;     // clip space, non-indexed triangles
    std::vector<Vec3> colour;  // per vertex
};

Scene random_scene(std::uint64_t seed, int triangles) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f), size(0.01f, 0.6f);
    Scene s;
    auto colour = [&] { return Vec3{unit(rng), unit(rng), unit(rng)}; };
    for (int t = 0; t < triangles; ++t) {
        const int kind = t % 10;
        if (kind == 9 && t > 0) {  // a coplanar duplicate of the previous triangle in another colour
            for (int k = 0; k < 3; ++k) {
                s.pos.push_back(s.pos[s.pos.size() - 3]);
                s.colour.push_back(colour());
            }
            continue;
        }
        const float cx = u(rng) * 1.2f, cy = u(rng) * 1.2f, r = size(rng);
        for (int k = 0; k < 3; ++k) {
            Vec4 p{cx + u(rng) * r, cy + u(rng) * r, unit(rng), 1.0f};
            // Now and then a huge one, far back, crossing the guard band and the near or far plane.
            if (t % 40 == 7) p = Vec4{u(rng) * 300, u(rng) * 300, k == 0 ? -0.5f : 0.7f + unit(rng) * 0.6f, 1};
            const float w = kind >= 5 ? 0.25f + 3.0f * unit(rng) : 1.0f;  // perspective
            s.pos.push_back(Vec4{p.x * w, p.y * w, p.z * w, w});
            s.colour.push_back(colour());
        }
    }
    return s;
}

// Colour from the interpolated varyings and their screen-space derivatives (exercises that path too).
struct DerivativeShader {
    static constexpr int k_varyings = 3;
    static constexpr bool k_derivatives = true;
    const Scene* scene;
    Vec4 vertex(std::uint32_t i, Varyings<3>& out) const {
        out.set(0, scene->colour[i]);
        return scene->pos[i];
    }
    Vec4 fragment(const FragmentIn<3>& in) const {
        return Vec4{in.v[0], in.v[1] + 8.0f * in.ddx[1], in.v[2] + 8.0f * in.ddy[2], 1.0f};
    }
};

struct Output {
    std::vector<Rgba8> colour;
    std::vector<float> depth;
    DrawStats opaque_stats;
};

Output render(const Scene& opaque, const Scene& blended, RendererConfig config, int repeats = 1) {
    Renderer renderer(config);
    Framebuffer fb(250, 190);  // not a multiple of any tile size
    DrawStats stats;
    for (int r = 0; r < repeats; ++r) {
        fb.clear(Vec4{0.1f, 0.2f, 0.3f, 1.0f}, 1.0f);
        DrawState state;
        state.cull = CullMode::none;
        state.depth_test = DepthTest::less;
        stats = renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(opaque.pos.size()), {}}, DerivativeShader{&opaque});
        state.blend = Blend::alpha;
        state.depth_write = false;
        state.depth_test = DepthTest::lequal;
        const auto translucent = make_shader<3>(
            [&](std::uint32_t i, Varyings<3>& out) {
                out.set(0, blended.colour[i]);
                return blended.pos[i];
            },
            [](const FragmentIn<3>& in) { return Vec4{in.v[0], in.v[1], in.v[2], 0.4f}; });
        renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(blended.pos.size()), {}}, translucent);
    }
    Output out;
    out.colour.assign(fb.colour_data(), fb.colour_data() + 250 * 190);
    out.depth.assign(fb.depth_data(), fb.depth_data() + 250 * 190);
    out.opaque_stats = stats;
    return out;
}

bool same_bytes(const Output& a, const Output& b) {
    return std::memcmp(a.colour.data(), b.colour.data(), a.colour.size() * sizeof(Rgba8)) == 0 &&
           std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

TEST(Determinism, IdenticalBytesForEveryThreadCountAndTileSize) {
    const Scene opaque = random_scene(41, 6000);  // 6000 triangles: several front-end chunks
    const Scene blended = random_scene(42, 1500);
    const Output reference = render(opaque, blended, {.threads = 1, .tile_size = 64});

    // The scene is not trivial: most pixels drawn, many distinct colours and depths.
    std::set<std::uint32_t> colours;
    std::set<float> depths;
    int background = 0;
    for (std::size_t i = 0; i < reference.colour.size(); ++i) {
        const Rgba8 c = reference.colour[i];
        colours.insert(std::uint32_t{c.r} | std::uint32_t{c.g} << 8 | std::uint32_t{c.b} << 16);
        depths.insert(reference.depth[i]);
        background += reference.depth[i] == 1.0f;
    }
    EXPECT_GT(colours.size(), 5000u);
    EXPECT_GT(depths.size(), 10000u);
    EXPECT_LT(background, static_cast<int>(reference.depth.size() / 10));
    EXPECT_GT(reference.opaque_stats.triangles_clipped, 100u);
    EXPECT_GT(reference.opaque_stats.triangles_rasterized, 4500u);  // less the smallest that cover no pixel

    for (int threads : {1, 2, 3, 8})
        for (int tile : {8, 16, 32, 64}) {
            const Output out = render(opaque, blended, {.threads = threads, .tile_size = tile});
            EXPECT_TRUE(same_bytes(out, reference)) << "threads " << threads << ", tile " << tile;
        }
    // Batches of any size (down to one triangle per batch) draw the same bytes.
    for (int batch : {1, 7, 1000})
        for (int threads : {1, 3}) {
            const Output out = render(opaque, blended, {.threads = threads, .tile_size = 32, .batch_triangles = batch});
            EXPECT_TRUE(same_bytes(out, reference)) << "batch " << batch << ", threads " << threads;
        }
    // A renderer reused across draws (scratch memory kept) gives the same bytes again.
    EXPECT_TRUE(same_bytes(render(opaque, blended, {.threads = 3, .tile_size = 16}, 3), reference));
}

// A batch of 2^18 triangles a thread or more is split into three chunks a thread of decreasing size
// (Renderer::run_front_end) rather than two equal ones: the same bytes as one thread's two chunks.
// Random halves of the cells of three grids of vertices at three depths, split along either diagonal
// (cells under half a pixel: most triangles cover no pixel centre, so few records), so that where
// two overlapping halves in different colours cover a pixel at the nearest depth the first wins: the
// chunks' order decides it. Each triangle is counted once (no gap or overlap between chunks).
TEST(Determinism, LargeBatchesSplitUnevenlyDrawTheSameBytes) {
    constexpr std::uint32_t k_triangles = (1u << 19) + 1001;  // three chunks a thread with two threads
    constexpr int k_w = 96, k_h = 64, k_grid = 256;
    std::uint32_t state = 44;
    const auto next = [&] {  // xorshift32: cheap enough for half a million triangles
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return state;
    };
    Scene s;
    for (int layer = 0; layer < 3; ++layer)
        for (int j = 0; j < k_grid; ++j)
            for (int i = 0; i < k_grid; ++i) {
                const float step = 2.0f / (k_grid - 1);
                s.pos.push_back(Vec4{-1.0f + step * static_cast<float>(i), -1.0f + step * static_cast<float>(j),
                                     0.25f * static_cast<float>(1 + layer), 1.0f});
                s.colour.push_back(Vec3{static_cast<float>(next() & 255) / 255.0f, static_cast<float>(next() & 255) / 255.0f,
                                        static_cast<float>(next() & 255) / 255.0f});
            }
    std::vector<std::uint32_t> indices;
    indices.reserve(3 * std::size_t{k_triangles});
    for (std::uint32_t t = 0; t < k_triangles; ++t) {
        const std::uint32_t r = next(), layer = t % 3, i = r % (k_grid - 1), j = (r >> 8) % (k_grid - 1);
        const std::uint32_t v = layer * k_grid * k_grid + j * k_grid + i;
        switch (r >> 30) {  // either half of either diagonal's split: halves of the two splits overlap
            case 0: indices.insert(indices.end(), {v, v + 1, v + k_grid}); break;
            case 1: indices.insert(indices.end(), {v + 1, v + k_grid + 1, v + k_grid}); break;
            case 2: indices.insert(indices.end(), {v, v + 1, v + k_grid + 1}); break;
            default: indices.insert(indices.end(), {v, v + k_grid + 1, v + k_grid}); break;
        }
    }
    const auto draw = [&](int threads) {
        Renderer renderer({.threads = threads, .tile_size = 32});
        Framebuffer fb(k_w, k_h);
        fb.clear(Vec4{0, 0, 0, 1}, 1.0f);
        DrawState state;
        state.cull = CullMode::none;
        state.depth_test = DepthTest::less;
        const auto shader = make_shader<3>(
            [&](std::uint32_t i, Varyings<3>& out) {
                out.set(0, s.colour[i]);
                return s.pos[i];
            },
            [](const FragmentIn<3>& in) { return Vec4{in.v[0], in.v[1], in.v[2], 1.0f}; });
        Output out;
        out.opaque_stats = renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(s.pos.size()), indices}, shader);
        out.colour.assign(fb.colour_data(), fb.colour_data() + k_w * k_h);
        out.depth.assign(fb.depth_data(), fb.depth_data() + k_w * k_h);
        return out;
    };
    const Output reference = draw(1);
    EXPECT_EQ(reference.opaque_stats.triangles_in, k_triangles);
    int nearest = 0;
    for (const float d : reference.depth) nearest += d == 0.25f;
    EXPECT_GT(nearest, k_w * k_h / 2);  // most pixels drawn by the nearest layer
    const Output two = draw(2);
    EXPECT_EQ(two.opaque_stats.triangles_in, k_triangles);
    EXPECT_EQ(two.opaque_stats.triangles_rasterized, reference.opaque_stats.triangles_rasterized);
    EXPECT_TRUE(same_bytes(two, reference));
}

// The comparison can fail: submission order matters (coplanar duplicates, blending), so drawing the
// same triangles in another order gives different bytes.
TEST(Determinism, ComparisonSeesOrderChanges) {
    const Scene opaque = random_scene(41, 6000);
    const Scene blended = random_scene(42, 1500);
    Scene reversed = opaque;
    const std::size_t n = reversed.pos.size() / 3;
    for (std::size_t t = 0; t < n / 2; ++t)
        for (int k = 0; k < 3; ++k) {
            std::swap(reversed.pos[t * 3 + k], reversed.pos[(n - 1 - t) * 3 + k]);
            std::swap(reversed.colour[t * 3 + k], reversed.colour[(n - 1 - t) * 3 + k]);
        }
    EXPECT_FALSE(same_bytes(render(opaque, blended, {.threads = 2, .tile_size = 16}),
                            render(reversed, blended, {.threads = 2, .tile_size = 16})));
}

// The SIMD kernels (coverage, the depth pass) give the scalar specification's bytes on every ISA the
// CPU runs, for every depth test, with and without depth writes, at tile sizes narrower than a
// vector and targets whose width is not a multiple of one.
struct DerivativeShaderEveryFragment : DerivativeShader {
    static constexpr bool k_shade_hidden = true;  // the one-pass drawing order
};

Output render_with_test(const Scene& scene, DepthTest test, bool write, RendererConfig config, bool one_pass = false) {
    Renderer renderer(config);
    Framebuffer fb(250, 190);
    fb.clear(Vec4{0.1f, 0.2f, 0.3f, 1.0f}, test == DepthTest::greater ? 0.0f : 0.6f);
    DrawState state;
    state.cull = CullMode::none;
    state.depth_test = test;
    state.depth_write = write;
    const DrawInput input{static_cast<std::uint32_t>(scene.pos.size()), {}};
    if (one_pass)
        renderer.draw(fb, state, input, DerivativeShaderEveryFragment{{&scene}});
    else
        renderer.draw(fb, state, input, DerivativeShader{&scene});
    Output out;
    out.colour.assign(fb.colour_data(), fb.colour_data() + 250 * 190);
    out.depth.assign(fb.depth_data(), fb.depth_data() + 250 * 190);
    return out;
}

using facet_test::IsaGuard;

TEST(Determinism, IdenticalBytesOnEveryIsaAndForEveryDepthTest) {
    IsaGuard guard;
    const Scene scene = random_scene(43, 3000);
    const std::vector<std::string> isas = available_isas();
    ASSERT_GE(isas.size(), 2u);  // at least one SIMD target besides "scalar" on x86-64
    for (DepthTest test : {DepthTest::less, DepthTest::lequal, DepthTest::equal, DepthTest::greater, DepthTest::always})
        for (bool write : {true, false}) {
            ASSERT_TRUE(select_isa("scalar"));
            const Output reference = render_with_test(scene, test, write, {.threads = 1, .tile_size = 64});
            // Shading only visible pixels draws what shading every fragment in order draws.
            EXPECT_TRUE(same_bytes(render_with_test(scene, test, write, {.threads = 1, .tile_size = 64}, true), reference))
                << "one-pass order, depth test " << static_cast<int>(test) << ", write " << write;
            for (const std::string& isa : isas) {
                ASSERT_TRUE(select_isa(isa));
                for (int tile : {8, 64}) {
                    const Output out = render_with_test(scene, test, write, {.threads = 2, .tile_size = tile});
                    EXPECT_TRUE(same_bytes(out, reference)) << isa << ", depth test " << static_cast<int>(test)
                                                            << ", write " << write << ", tile " << tile;
                }
            }
        }
    // The reference is not trivial for the common case.
    ASSERT_TRUE(select_isa("best"));
    const Output less = render_with_test(scene, DepthTest::less, true, {.threads = 1, .tile_size = 64});
    std::set<std::uint32_t> colours;
    for (const Rgba8 c : less.colour) colours.insert(std::uint32_t{c.r} | std::uint32_t{c.g} << 8 | std::uint32_t{c.b} << 16);
    EXPECT_GT(colours.size(), 3000u);
}

}  // namespace
