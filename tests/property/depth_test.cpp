// Property: the fixed-function per-pixel state. Depth test modes (never / less / lequal / equal /
// greater / always) with and without depth writes, discard from the fragment stage, and face culling
// (none / back / front, both windings, both FrontFace conventions).
//
// Depth: two overlapping triangles A (drawn first) and B (drawn second), each at one constant window
// depth (0.25, 0.5 or 0.75: exact in float, and a constant depth plane interpolates exactly), over a
// depth buffer cleared to 0.25, 0.5 or 1. The expected picture follows the definitions directly: per
// pixel, for A then B where they cover it (coverage from the reference rasterizer), the fragment passes
// if `z OP stored` and then writes its colour, and its depth if depth writes are on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "facet/math/transform.hpp"
#include "facet/renderer.hpp"
#include "support/reference_raster.hpp"

namespace {

using namespace facet;
namespace R = facet_test::raster;

constexpr int W = 64, H = 64;
const Rect k_vp{0, 0, W, H};

// A: a big triangle on the left, B: one on the right; they overlap in the middle.
const R::Fixed k_a[3] = {{4 * 256 + 17, 6 * 256 + 3}, {44 * 256 + 130, 20 * 256 + 40}, {8 * 256 + 200, 58 * 256 + 99}};
const R::Fixed k_b[3] = {{60 * 256 + 5, 4 * 256 + 77}, {56 * 256 + 128, 60 * 256 + 128}, {18 * 256 + 33, 30 * 256 + 180}};
const Vec4 k_colour_a{1, 0, 0, 1}, k_colour_b{0, 0, 1, 1}, k_clear{0, 0, 0, 0};

const char* name(DepthTest d) {
    static const char* names[] = {"never", "less", "lequal", "equal", "greater", "always"};
    return names[static_cast<int>(d)];
}

bool passes(DepthTest d, float z, float stored) {  // the definitions, by name
    switch (d) {
        case DepthTest::never: return false;
        case DepthTest::less: return z < stored;
        case DepthTest::lequal: return z <= stored;
        case DepthTest::equal: return z == stored;
        case DepthTest::greater: return z > stored;
        case DepthTest::always: return true;
    }
    return false;
}

// Draws A then B in one draw call, with the given depth test, writes, clear depth and depths.
// Blend::alpha draws in the one-pass order (shade_tile) instead of the visible-only order; the
// colours are opaque, so the bytes are the same.
Framebuffer draw_pair(DepthTest test, bool write, float clear_depth, float za, float zb, int threads = 1,
                      Blend blend = Blend::none) {
    std::vector<Vec4> pos;
    for (const R::Fixed& p : k_a) pos.push_back(R::clip_from_fixed(p, k_vp, za));
    for (const R::Fixed& p : k_b) pos.push_back(R::clip_from_fixed(p, k_vp, zb));
    const auto coloured = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, i < 3 ? k_colour_a : k_colour_b);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    Framebuffer fb(W, H);
    fb.clear(k_clear, clear_depth);
    DrawState state;
    state.cull = CullMode::none;
    state.depth_test = test;
    state.depth_write = write;
    state.blend = blend;
    Renderer({.threads = threads, .tile_size = 16}).draw(fb, state, DrawInput{6, {}}, coloured);
    return fb;
}

// Triangles of per-vertex colours (pos in clip space) drawn over k_clear at depth 1, culling off.
Framebuffer draw_coloured(const std::vector<Vec4>& pos, const std::vector<Vec4>& colour, DrawState state, int threads,
                          DrawStats* stats = nullptr) {
    const auto shader = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, colour[i]);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    Framebuffer fb(W, H);
    fb.clear(k_clear, 1.0f);
    state.cull = CullMode::none;
    const DrawStats s = Renderer({.threads = threads, .tile_size = 16})
                            .draw(fb, state, DrawInput{static_cast<std::uint32_t>(pos.size()), {}}, shader);
    if (stats) *stats = s;
    return fb;
}

struct Expected {
    std::vector<Rgba8> colour;
    std::vector<float> depth;
};

Expected model(DepthTest test, bool write, float clear_depth, float za, float zb) {
    const R::Mask ma = R::rasterize(k_a, W, H, {0, 0, W, H}), mb = R::rasterize(k_b, W, H, {0, 0, W, H});
    Expected e{std::vector<Rgba8>(W * H, to_rgba8(k_clear)), std::vector<float>(W * H, clear_depth)};
    for (std::size_t i = 0; i < e.colour.size(); ++i) {
        const struct {
            bool covered;
            float z;
            Vec4 colour;
        } frags[2] = {{ma[i] != 0, za, k_colour_a}, {mb[i] != 0, zb, k_colour_b}};
        for (const auto& f : frags) {
            if (!f.covered || !passes(test, f.z, e.depth[i])) continue;
            e.colour[i] = to_rgba8(f.colour);
            if (write) e.depth[i] = f.z;
        }
    }
    return e;
}

TEST(DepthTest, EveryModeAndWriteFlagFollowsTheDefinition) {
    const R::Mask ma = R::rasterize(k_a, W, H, {0, 0, W, H}), mb = R::rasterize(k_b, W, H, {0, 0, W, H});
    int only_a = 0, only_b = 0, both = 0;
    for (std::size_t i = 0; i < ma.size(); ++i) {
        only_a += ma[i] && !mb[i];
        only_b += mb[i] && !ma[i];
        both += ma[i] && mb[i];
    }
    ASSERT_GT(only_a, 200);
    ASSERT_GT(only_b, 200);
    ASSERT_GT(both, 200);
    const float values[] = {0.25f, 0.5f, 0.75f};
    for (DepthTest test : {DepthTest::never, DepthTest::less, DepthTest::lequal, DepthTest::equal, DepthTest::greater,
                           DepthTest::always})
        for (bool write : {true, false})
            for (float clear : {0.25f, 0.5f, 1.0f})
                for (float za : values)
                    for (float zb : values)
                        for (Blend blend : {Blend::none, Blend::alpha}) {
                            const Framebuffer fb = draw_pair(test, write, clear, za, zb, za == zb ? 2 : 1, blend);
                            const Expected e = model(test, write, clear, za, zb);
                            int wrong = 0;
                            for (std::size_t i = 0; i < e.colour.size(); ++i)
                                wrong += fb.colour_data()[i] != e.colour[i] || fb.depth_data()[i] != e.depth[i];
                            EXPECT_EQ(wrong, 0) << name(test) << (write ? " write" : " no-write") << ", clear " << clear
                                                << ", A at " << za << ", B at " << zb
                                                << (blend == Blend::alpha ? ", one-pass order" : ", visible-only order");
                        }
}

// The one-pass order's run-time depth test (detail::depth_passes_in) against the definitions, on
// the values where comparisons are tricky: signed zeros, infinities, NaN, subnormals, neighbours.
TEST(DepthTest, RunTimeDepthTestFollowsTheDefinitionOnSpecialValues) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float values[] = {0.0f, -0.0f, 1e-45f, -1e-45f, 0.5f, std::nextafter(0.5f, 1.0f), 1.0f, -1.0f, inf, -inf, nan};
    for (DepthTest test : {DepthTest::never, DepthTest::less, DepthTest::lequal, DepthTest::equal, DepthTest::greater,
                           DepthTest::always}) {
        const std::uint32_t set = detail::depth_pass_set(test);
        for (float z : values)
            for (float stored : values)
                EXPECT_EQ(detail::depth_passes_in(set, z, stored), passes(test, z, stored))
                    << name(test) << ": z " << z << ", stored " << stored;
    }
}

// The same, spelled out by hand for the overlap region, so the model above is not the only witness.
TEST(DepthTest, HandCheckedOverlapWinners) {
    const R::Mask ma = R::rasterize(k_a, W, H, {0, 0, W, H}), mb = R::rasterize(k_b, W, H, {0, 0, W, H});
    std::size_t overlap = 0, a_only = 0, b_only = 0, outside = 0;
    for (std::size_t i = 0; i < ma.size(); ++i) {
        if (ma[i] && mb[i]) overlap = i;
        if (ma[i] && !mb[i]) a_only = i;
        if (!ma[i] && mb[i]) b_only = i;
        if (!ma[i] && !mb[i]) outside = i;
    }
    const Rgba8 red = to_rgba8(k_colour_a), blue = to_rgba8(k_colour_b), none = to_rgba8(k_clear);
    auto at = [](const Framebuffer& fb, std::size_t i) { return fb.colour_data()[i]; };
    // A nearer (0.25) than B (0.75), cleared to 1.
    Framebuffer fb = draw_pair(DepthTest::less, true, 1.0f, 0.25f, 0.75f);
    EXPECT_EQ(at(fb, overlap), red);
    EXPECT_EQ(fb.depth_data()[overlap], 0.25f);
    EXPECT_EQ(at(fb, b_only), blue);
    EXPECT_EQ(at(fb, outside), none);
    EXPECT_EQ(fb.depth_data()[outside], 1.0f);
    // greater: nothing beats a cleared 1; from a cleared 0.25 the farther B wins the overlap.
    fb = draw_pair(DepthTest::greater, true, 1.0f, 0.25f, 0.75f);
    EXPECT_EQ(at(fb, overlap), none);
    fb = draw_pair(DepthTest::greater, true, 0.25f, 0.5f, 0.75f);
    EXPECT_EQ(at(fb, overlap), blue);
    EXPECT_EQ(fb.depth_data()[overlap], 0.75f);
    EXPECT_EQ(at(fb, a_only), red);
    // less without depth writes: B is compared with the cleared value, not with A, so B wins the overlap.
    fb = draw_pair(DepthTest::less, false, 1.0f, 0.25f, 0.75f);
    EXPECT_EQ(at(fb, overlap), blue);
    EXPECT_EQ(fb.depth_data()[overlap], 1.0f);
    // Equal depths: less keeps the first, lequal takes the second.
    EXPECT_EQ(at(draw_pair(DepthTest::less, true, 1.0f, 0.5f, 0.5f), overlap), red);
    EXPECT_EQ(at(draw_pair(DepthTest::lequal, true, 1.0f, 0.5f, 0.5f), overlap), blue);
    // equal: only fragments at exactly the stored depth.
    fb = draw_pair(DepthTest::equal, true, 0.5f, 0.5f, 0.75f);
    EXPECT_EQ(at(fb, overlap), red);
    EXPECT_EQ(at(fb, b_only), none);
    // always: the last one drawn; never: nothing, depth untouched.
    EXPECT_EQ(at(draw_pair(DepthTest::always, true, 0.25f, 0.75f, 0.5f), overlap), blue);
    fb = draw_pair(DepthTest::never, true, 0.5f, 0.25f, 0.25f);
    EXPECT_EQ(at(fb, overlap), none);
    EXPECT_EQ(at(fb, a_only), none);
    EXPECT_EQ(fb.depth_data()[overlap], 0.5f);
}

// A triangle with sloped depth drawn twice: the second pass computes exactly the same depth at every
// pixel, so `equal` and `lequal` pass everywhere the first pass drew, and `less` nowhere.
TEST(DepthTest, SecondPassOfTheSameGeometryMatchesExactly) {
    const R::Fixed t[3] = {{3 * 256 + 11, 2 * 256 + 200}, {61 * 256 + 100, 9 * 256 + 7}, {20 * 256 + 3, 62 * 256 + 150}};
    const float z[3] = {0.1f, 0.93f, 0.47f}, w[3] = {1.0f, 2.7f, 0.6f};
    std::vector<Vec4> pos;
    for (int k = 0; k < 3; ++k) pos.push_back(R::clip_from_fixed(t[k], k_vp, z[k], w[k]));
    for (DepthTest second : {DepthTest::equal, DepthTest::lequal, DepthTest::less}) {
        Framebuffer fb(W, H);
        fb.clear(k_clear, 1.0f);
        Renderer renderer({.threads = 2, .tile_size = 8});
        DrawState state;
        state.cull = CullMode::none;
        const Vec4 first_colour{1, 0, 0, 1}, second_colour{0, 1, 0, 1};
        Vec4 colour = first_colour;
        const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                           [&](const FragmentIn<0>&) { return colour; });
        renderer.draw(fb, state, DrawInput{3, {}}, shader);
        const std::vector<float> first_depth(fb.depth_data(), fb.depth_data() + W * H);
        colour = second_colour;
        state.depth_test = second;
        renderer.draw(fb, state, DrawInput{3, {}}, shader);
        int drawn = 0;
        for (int i = 0; i < W * H; ++i) {
            if (first_depth[i] == 1.0f) continue;  // not covered (covered pixels have depth < 0.94)
            ++drawn;
            const Rgba8 want = to_rgba8(second == DepthTest::less ? first_colour : second_colour);
            ASSERT_EQ(fb.colour_data()[i], want) << name(second) << " pixel " << i;
            ASSERT_EQ(fb.depth_data()[i], first_depth[i]);
        }
        EXPECT_GT(drawn, 1000);
    }
}

// A tile's shading records are written for its listed triangles from the first that owns a pixel
// when its depth pass ends; those before it were hidden everywhere by later ones. 8,192 far
// triangles (one per half pixel of the target) fill the first chunks' bins; a near triangle that
// holds the whole target, clipped to the guard band (its varyings in its chunk's clip extras), comes
// in the second chunk, and a small nearer one in the last. The image is the one of the two near
// triangles drawn alone: a record skipped for a triangle that owns a pixel, or read from another
// chunk's extras, would show in their colours.
TEST(DepthTest, TrianglesHiddenByLaterChunksLeaveTheNearOnesAsDrawnAlone) {
    std::vector<Vec4> far_pos, far_colour;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const R::Fixed c[4] = {{x * 256, y * 256}, {x * 256 + 256, y * 256}, {x * 256 + 256, y * 256 + 256}, {x * 256, y * 256 + 256}};
            for (int k : {0, 1, 2, 0, 2, 3}) {
                far_pos.push_back(R::clip_from_fixed(c[k], k_vp, 0.75f));
                far_colour.push_back(Vec4{static_cast<float>(x) / W, static_cast<float>(y) / H, static_cast<float>(k) / 4, 1});
            }
        }
    const std::vector<Vec4> near_pos = {{-1e6f, -1e6f, 0.5f, 1}, {1e6f, -1e6f, 0.5f, 1}, {0, 1e6f, 0.5f, 1},
                                        R::clip_from_fixed(k_a[0], k_vp, 0.25f), R::clip_from_fixed(k_a[1], k_vp, 0.25f),
                                        R::clip_from_fixed(k_a[2], k_vp, 0.25f)};
    const std::vector<Vec4> near_colour = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 0, 1}, {0, 1, 1, 1}, {1, 0, 1, 1}};
    // Far triangles, the near one as triangle 2,100 (in the second of 4 chunks of 2,050 at 2 threads),
    // far ones again, the nearer one last.
    std::vector<Vec4> pos, colour;
    const std::size_t split = 3 * 2100;
    for (std::size_t i = 0; i < far_pos.size(); ++i) {
        if (i == split) {
            pos.insert(pos.end(), near_pos.begin(), near_pos.begin() + 3);
            colour.insert(colour.end(), near_colour.begin(), near_colour.begin() + 3);
        }
        pos.push_back(far_pos[i]);
        colour.push_back(far_colour[i]);
    }
    pos.insert(pos.end(), near_pos.begin() + 3, near_pos.end());
    colour.insert(colour.end(), near_colour.begin() + 3, near_colour.end());
    DrawStats stats;
    const Framebuffer all = draw_coloured(pos, colour, DrawState{}, 2, &stats);
    const Framebuffer alone = draw_coloured(near_pos, near_colour, DrawState{}, 2);
    EXPECT_EQ(stats.triangles_clipped, 1u);
    int nearer = 0;
    for (int i = 0; i < W * H; ++i) {
        ASSERT_EQ(all.colour_data()[i], alone.colour_data()[i]) << "pixel " << i;
        ASSERT_EQ(all.depth_data()[i], alone.depth_data()[i]) << "pixel " << i;
        nearer += alone.depth_data()[i] == 0.25f;
    }
    EXPECT_GT(nearer, 500);
    EXPECT_LT(nearer, W * H - 500);
}

// A bin's pieces (k_bin_piece records) that lie behind the whole tile are passed over unread (their
// depth floors above the tile's largest depth); a piece may be passed over only when none of its
// triangles would pass anywhere. A near layer of half-pixel triangles at depth 0.5 over the whole
// target, then a far layer at 0.75 into which a few tilted triangles are mixed: their first vertex at
// 0.75 (the depth plane's origin), the others at 0.25, so that they reach in front of the near layer
// near those. The image is the one the one-pass order draws (Blend::alpha with opaque colours: the
// same bytes, and no pieces passed over): a piece passed over for a floor above a pixel it reaches
// would show as a missing tilted triangle.
TEST(DepthTest, PiecesBehindTheWholeTileAreDrawnAsIfDrawn) {
    std::vector<Vec4> pos, colour, tilted_pos, tilted_colour;
    for (int k = 0; k < 9; ++k) {  // 12 x 6 pixels each, spread over the tiles
        const int x = 3 + (k % 3) * 21, y = 5 + (k / 3) * 21;
        const R::Fixed c[3] = {{x * 256 + 40, y * 256 + 30}, {(x + 12) * 256 + 7, (y + 2) * 256 + 99}, {(x + 3) * 256 + 11, (y + 6) * 256 + 70}};
        const float z[3] = {0.75f, 0.25f, 0.25f};
        for (int v = 0; v < 3; ++v) {
            tilted_pos.push_back(R::clip_from_fixed(c[v], k_vp, z[v]));
            tilted_colour.push_back(Vec4{1, static_cast<float>(k) / 9, static_cast<float>(v) / 3, 1});
        }
    }
    for (float z : {0.5f, 0.75f})
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const R::Fixed c[4] = {{x * 256, y * 256}, {x * 256 + 256, y * 256}, {x * 256 + 256, y * 256 + 256}, {x * 256, y * 256 + 256}};
                for (int k : {0, 1, 2, 0, 2, 3}) {
                    pos.push_back(R::clip_from_fixed(c[k], k_vp, z));
                    colour.push_back(Vec4{static_cast<float>(x) / W, static_cast<float>(y) / H, z, 1});
                }
                // The tilted triangles among the far layer, each just before the far one at its first pixel.
                const int k = (x - 3) / 21 + (y - 5) / 21 * 3;
                if (z == 0.75f && (x - 3) % 21 == 0 && (y - 5) % 21 == 0 && x >= 3 && y >= 5) {
                    pos.insert(pos.end() - 6, tilted_pos.begin() + 3 * k, tilted_pos.begin() + 3 * k + 3);
                    colour.insert(colour.end() - 6, tilted_colour.begin() + 3 * k, tilted_colour.begin() + 3 * k + 3);
                }
            }
    ASSERT_EQ(pos.size(), 2u * W * H * 6 + tilted_pos.size());
    const auto draw = [&](DepthTest test, Blend blend) {
        DrawState state;
        state.depth_test = test;
        state.blend = blend;
        return draw_coloured(pos, colour, state, 1);
    };
    for (DepthTest test : {DepthTest::less, DepthTest::lequal}) {
        const Framebuffer visible_only = draw(test, Blend::none);
        const Framebuffer one_pass = draw(test, Blend::alpha);
        int tilted = 0;
        for (int i = 0; i < W * H; ++i) {
            ASSERT_EQ(visible_only.colour_data()[i], one_pass.colour_data()[i]) << name(test) << " pixel " << i;
            ASSERT_EQ(visible_only.depth_data()[i], one_pass.depth_data()[i]) << name(test) << " pixel " << i;
            tilted += one_pass.depth_data()[i] < 0.5f;
        }
        EXPECT_GT(tilted, 200) << name(test);
    }
}

// Discard: a fragment function returning std::optional<Vec4> with nullopt leaves colour and depth
// exactly as they were (depth test passing, depth writes on, with and without blending).
TEST(DepthTest, DiscardLeavesColourAndDepthUntouched) {
    for (Blend blend : {Blend::none, Blend::alpha}) {
        Framebuffer fb(W, H);
        fb.clear(Vec4{0.2f, 0.4f, 0.6f, 1.0f}, 1.0f);
        Renderer renderer({.threads = 2, .tile_size = 16});
        DrawState state;
        state.cull = CullMode::none;
        // A background over the whole target at depth 0.9.
        const std::vector<Vec4> back = {{-1, -1, 0.9f, 1}, {3, -1, 0.9f, 1}, {-1, 3, 0.9f, 1}};
        renderer.draw(fb, state, DrawInput{3, {}},
                      make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return back[i]; },
                                     [](const FragmentIn<0>&) { return Vec4{1, 0, 0, 1}; }));
        const std::vector<Rgba8> colour_before(fb.colour_data(), fb.colour_data() + W * H);
        const std::vector<float> depth_before(fb.depth_data(), fb.depth_data() + W * H);
        // In front of it, a triangle that discards every pixel with (x + 2y) % 3 == 0.
        std::vector<Vec4> front;
        for (const R::Fixed& p : k_a) front.push_back(R::clip_from_fixed(p, k_vp, 0.5f));
        auto discards = [](int x, int y) { return (x + 2 * y) % 3 == 0; };
        state.blend = blend;
        renderer.draw(fb, state, DrawInput{3, {}},
                      make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return front[i]; },
                                     [&](const FragmentIn<0>& in) -> std::optional<Vec4> {
                                         if (discards(static_cast<int>(in.pos_screen.x), static_cast<int>(in.pos_screen.y)))
                                             return std::nullopt;
                                         return Vec4{0, 1, 0, 1};
                                     }));
        const R::Mask covered = R::rasterize(k_a, W, H, {0, 0, W, H});
        int kept = 0, written = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * W + x;
                if (covered[i] && !discards(x, y)) {
                    ++written;
                    EXPECT_EQ(fb.colour_data()[i], to_rgba8(Vec4{0, 1, 0, 1})) << x << "," << y;
                    EXPECT_EQ(fb.depth_data()[i], 0.5f) << x << "," << y;
                } else {
                    kept += covered[i] != 0;
                    EXPECT_EQ(fb.colour_data()[i], colour_before[i]) << x << "," << y;
                    EXPECT_EQ(fb.depth_data()[i], depth_before[i]) << x << "," << y;
                }
            }
        EXPECT_GT(kept, 100);
        EXPECT_GT(written, 200);
    }
}

// Culling. A triangle counter-clockwise as the viewer sees it (NDC, y up) and its mirror image.
// Front faces are those whose winding matches front_face; back culling drops the others, front
// culling drops the front ones, none drops nothing. The fragment stage sees front_facing accordingly.
TEST(Culling, NoneBackFrontWithBothWindingsAndBothConventions) {
    const Vec4 ccw[3] = {{-0.5f, -0.5f, 0.5f, 1}, {0.5f, -0.5f, 0.5f, 1}, {0.0f, 0.5f, 0.5f, 1}};
    // In pixels (16, 48), (48, 48), (32, 16): the reference says how many pixels it covers.
    const R::Fixed screen[3] = {{16 * 256, 48 * 256}, {48 * 256, 48 * 256}, {32 * 256, 16 * 256}};
    const R::Mask m = R::rasterize(screen, W, H, {0, 0, W, H});
    const int area = static_cast<int>(std::count(m.begin(), m.end(), 1));
    ASSERT_GT(area, 400);
    for (bool viewer_ccw : {true, false})
        for (FrontFace face : {FrontFace::ccw, FrontFace::cw})
            for (CullMode cull : {CullMode::none, CullMode::back, CullMode::front}) {
                const std::vector<Vec4> pos = viewer_ccw ? std::vector<Vec4>{ccw[0], ccw[1], ccw[2]}
                                                         : std::vector<Vec4>{ccw[0], ccw[2], ccw[1]};
                const bool front = viewer_ccw == (face == FrontFace::ccw);
                const bool drawn = cull == CullMode::none || (cull == CullMode::back) == front;
                Framebuffer fb(W, H);
                fb.clear(k_clear, 1.0f);
                DrawState state;
                state.cull = cull;
                state.front_face = face;
                const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                                   [](const FragmentIn<0>& in) {
                                                       return in.front_facing ? Vec4{0, 1, 0, 1} : Vec4{1, 0, 1, 1};
                                                   });
                const DrawStats stats = Renderer({.threads = 1, .tile_size = 16}).draw(fb, state, DrawInput{3, {}}, shader);
                std::ostringstream what;
                what << (viewer_ccw ? "viewer-ccw" : "viewer-cw") << ", front_face " << (face == FrontFace::ccw ? "ccw" : "cw")
                     << ", cull " << static_cast<int>(cull);
                EXPECT_EQ(stats.triangles_culled, drawn ? 0u : 1u) << what.str();
                EXPECT_EQ(stats.triangles_rasterized, drawn ? 1u : 0u) << what.str();
                int pixels = 0;
                for (int i = 0; i < W * H; ++i) {
                    const Rgba8 c = fb.colour_data()[i];
                    if (c == to_rgba8(k_clear)) continue;
                    ++pixels;
                    EXPECT_EQ(c, to_rgba8(front ? Vec4{0, 1, 0, 1} : Vec4{1, 0, 1, 1})) << what.str();
                }
                EXPECT_EQ(pixels, drawn ? area : 0) << what.str();
            }
}

// "As seen by the viewer" through a real camera, including a triangle clipped by the near plane: a
// counter-clockwise triangle (seen from +Z) is front-facing from a camera on +Z and back-facing from
// one on -Z, whether or not it crosses the near plane.
TEST(Culling, FacingIsDecidedAsTheViewerSeesIt) {
    const Vec3 small[3] = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};      // ccw seen from +Z
    const Vec3 through[3] = {{-1, -1, 8}, {1, -1, 8}, {0, 1, -8}};   // ccw seen from +Z, long in z
    const Mat4 projection = perspective_rh_zo(radians(60.0f), 1.0f, 0.1f, 100.0f);
    for (const auto* tri : {small, through})
        for (float side : {1.0f, -1.0f}) {
            const Mat4 m = projection * look_at_rh({0, 0, 5 * side}, {0, 0, 0}, {0, 1, 0});
            std::vector<Vec4> pos;
            for (int k = 0; k < 3; ++k) pos.push_back(m * Vec4{tri[k], 1});
            Framebuffer fb(W, H);
            DrawState state;  // cull back, front_face ccw
            const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                               [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
            const DrawStats stats = Renderer({.threads = 1, .tile_size = 16}).draw(fb, state, DrawInput{3, {}}, shader);
            int pixels = 0;
            for (int i = 0; i < W * H; ++i) pixels += fb.colour_data()[i].r != 0;
            if (side > 0) {
                EXPECT_GT(pixels, 100) << (tri == small ? "small" : "through the near plane");
                EXPECT_EQ(stats.triangles_culled, 0u);
            } else {
                EXPECT_EQ(pixels, 0) << (tri == small ? "small" : "through the near plane");
                EXPECT_GE(stats.triangles_culled, 1u);
            }
            if (tri == through) {
                EXPECT_EQ(stats.triangles_clipped, 1u);
            }
        }
}

}  // namespace
