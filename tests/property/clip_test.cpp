// Property: clipping and projection. Geometry behind the eye, through the near plane, past the guard
// band, at absurd magnitudes or not finite at all renders what it geometrically should (or nothing),
// never crashes, never lets NaN or infinity into the framebuffer, never disturbs other triangles of
// the same draw; and varyings are interpolated perspective-correctly while depth is linear in screen
// space.
//
// Expected coverage is computed analytically here (horizon rows, half-planes, rectangles), in double
// precision from the exact vertex values; pixels within a stated distance of an edge whose position
// is only known up to float rounding are left out of the comparison, with the bound explained.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "facet/math/transform.hpp"
#include "facet/renderer.hpp"
#include "facet/shaders.hpp"
#include "support/reference_raster.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace R = facet_test::raster;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

// ---- a shader that counts hits and checks what it is given -------------------------------------

// Draws non-indexed triangles (consecutive triples of `pos`). Per vertex the varyings are `var` (three
// floats) or, when empty, (x, y, z) of the clip position. The fragment function counts hits per pixel,
// counts inputs that are not finite (varyings) or not in [0, 1] (depth), and writes colour = depth.
struct Drawn {
    Framebuffer fb;
    std::vector<int> hits;
    DrawStats stats;
    int bad_inputs = 0;
    int hit(int x, int y) const { return hits[static_cast<std::size_t>(y) * fb.width() + x]; }
};

Drawn draw_counting(const std::vector<Vec4>& pos, int width, int height, DrawState state,
                    RendererConfig config = {.threads = 2, .tile_size = 16}, const std::vector<Vec3>& var = {}) {
    Drawn out{Framebuffer(width, height), {}, {}, 0};
    out.fb.clear(Vec4{0, 0, 0, 0}, 1.0f);
    std::vector<std::atomic<int>> hits(static_cast<std::size_t>(width) * height);
    std::atomic<int> bad{0};
    const auto shader = make_shader<3>(
        [&](std::uint32_t i, Varyings<3>& v) {
            v.set(0, var.empty() ? pos[i].xyz() : var[i]);
            return pos[i];
        },
        [&](const FragmentIn<3>& in) {
            const int x = static_cast<int>(in.pos_screen.x), y = static_cast<int>(in.pos_screen.y);
            hits[static_cast<std::size_t>(y) * width + x].fetch_add(1, std::memory_order_relaxed);
            if (!(in.depth >= 0.0f && in.depth <= 1.0f) || !std::isfinite(in.v[0]) || !std::isfinite(in.v[1]) ||
                !std::isfinite(in.v[2]))
                bad.fetch_add(1, std::memory_order_relaxed);
            return Vec4{in.depth, in.depth, in.depth, 1};
        });
    out.stats = Renderer(config).draw(out.fb, state, DrawInput{static_cast<std::uint32_t>(pos.size()), {}}, shader);
    out.hits.resize(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) out.hits[i] = hits[i].load();
    out.bad_inputs = bad.load();
    return out;
}

DrawState state_always() {
    DrawState s;
    s.cull = CullMode::none;
    s.depth_test = DepthTest::always;
    return s;
}

// Every pixel: want(x, y) is 1 (hit exactly once), 0 (never hit) or -1 (not decided: at most once).
template <class Want>
::testing::AssertionResult coverage_is(const Drawn& d, Want want) {
    int wrong = 0, shown = 0, decided = 0;
    std::ostringstream detail;
    for (int y = 0; y < d.fb.height(); ++y)
        for (int x = 0; x < d.fb.width(); ++x) {
            const int w = want(x, y), got = d.hit(x, y);
            decided += w >= 0;
            if (got > 1 || (w >= 0 && got != w)) {
                if (shown++ < 10) detail << " (" << x << "," << y << "): " << got << " hits, want " << w << ";";
                ++wrong;
            }
        }
    if (wrong == 0) return ::testing::AssertionSuccess() << decided << " pixels decided";
    return ::testing::AssertionFailure() << wrong << " pixels wrong:" << detail.str();
}

// Depth buffer and colour: every depth value finite and in [0, 1]; where drawn, colour == depth.
::testing::AssertionResult framebuffer_sane(const Drawn& d) {
    for (int y = 0; y < d.fb.height(); ++y)
        for (int x = 0; x < d.fb.width(); ++x) {
            const float z = d.fb.depth(x, y);
            if (!std::isfinite(z) || z < 0.0f || z > 1.0f)
                return ::testing::AssertionFailure() << "depth " << z << " at " << x << "," << y;
            if (d.hit(x, y) > 0 && d.fb.colour(x, y) != to_rgba8(Vec4{z, z, z, 1}))
                return ::testing::AssertionFailure() << "colour does not match depth " << z << " at " << x << "," << y;
        }
    return ::testing::AssertionSuccess();
}

// ---- (a), (b) a ground plane from behind the eye to the distance ----------------------------------

// The plane y = 0, x in [-20000, 20000], z from +20000 (behind the eye) to -L, as two triangles. The
// eye is at height h looking along (0, -tan(phi), -1), i.e. pitched down by phi, with a 90 degree
// field of view (f = 1 / tan(45 deg) = 1) on a 256 x 256 target.
//   The horizon (directions (0, 0, -1)) is at ndc_y = tan(phi): row boundary 128 - 128 tan(phi).
//   The far edge (0, 0, -L) is at ndc_y = (L tan(phi) - h) / (L + h tan(phi)), a little lower.
// Rows whose centre is above the horizon are sky (never drawn), rows whose centre is below the far
// edge are ground (drawn exactly once): the plane is 4 times wider than the view there. The far-edge
// bound is computed in double and given 0.01 px of slack for the float matrices.
struct GroundCase {
    float tan_phi, h, L;
};

std::vector<Vec4> ground_plane(const GroundCase& g) {
    const Vec3 eye{0, g.h, 0};
    const Mat4 clip_from_world = perspective_rh_zo(radians(90.0f), 1.0f, 0.1f, 10000.0f) *
                                 look_at_rh(eye, eye + Vec3{0, -g.tan_phi, -1}, {0, 1, 0});
    const Vec4 c[4] = {{-20000, 0, -g.L, 1}, {20000, 0, -g.L, 1}, {20000, 0, 20000, 1}, {-20000, 0, 20000, 1}};
    std::vector<Vec4> pos;
    for (int k : {0, 1, 2, 0, 2, 3}) pos.push_back(clip_from_world * c[k]);
    return pos;
}

int ground_row_expectation(const GroundCase& g, int y) {
    const double horizon = 128.0 - 128.0 * g.tan_phi;
    const double far_ndc = (g.L * static_cast<double>(g.tan_phi) - g.h) / (g.L + g.h * static_cast<double>(g.tan_phi));
    const double far_edge = 128.0 - 128.0 * far_ndc;
    const double centre = y + 0.5;
    if (centre < horizon) return 0;
    if (centre > far_edge + 0.01) return 1;
    return -1;
}

const GroundCase k_ground_cases[] = {{0.0f, 2.0f, 5000.0f}, {0.25f, 2.0f, 5000.0f}, {0.0f, 1.0f, 500.0f}, {0.5f, 10.0f, 9000.0f}};

TEST(Clip, GroundPlaneFromBehindTheEyeShowsGroundBelowTheHorizon) {
    for (const GroundCase& g : k_ground_cases) {
        const std::vector<Vec4> pos = ground_plane(g);
        int behind = 0;
        for (const Vec4& p : pos) behind += p.w < 0;
        ASSERT_GT(behind, 0) << "the plane must reach behind the eye";
        for (RendererConfig config : {RendererConfig{.threads = 1, .tile_size = 64}, RendererConfig{.threads = 2, .tile_size = 8}}) {
            const Drawn d = draw_counting(pos, 256, 256, state_always(), config);
            EXPECT_TRUE(coverage_is(d, [&](int, int y) { return ground_row_expectation(g, y); }))
                << "tan(phi) " << g.tan_phi << ", h " << g.h << ", L " << g.L;
            int undecided_rows = 0;
            for (int y = 0; y < 256; ++y) undecided_rows += ground_row_expectation(g, y) < 0;
            EXPECT_LE(undecided_rows, 1);
            EXPECT_EQ(d.stats.triangles_in, 2u);
            EXPECT_EQ(d.stats.triangles_clipped, 2u);  // both cross the near plane
            EXPECT_EQ(d.stats.triangles_invalid, 0u);
            // (b) nothing non-finite reaches the shader or the framebuffer.
            EXPECT_EQ(d.bad_inputs, 0);
            EXPECT_TRUE(framebuffer_sane(d));
        }
    }
}

// (b) Random triangles of wild but finite clip coordinates (magnitudes from 1e-8 to 1e8, either sign,
// w sometimes exactly 0 or tiny), many of them crossing the near plane and the guard band: depth
// stays finite and in [0, 1] everywhere, and the fragment stage never sees a non-finite input.
TEST(Clip, WildCoordinatesNeverPutNonFiniteValuesInTheFramebuffer) {
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<float> exponent(-8.0f, 8.0f), unit(-1.0f, 1.0f);
    auto wild = [&]() {
        const float m = std::pow(10.0f, exponent(rng));
        return (rng() & 1) ? m : -m;
    };
    const int count = facet_test::sweep_size(5000, 2000);  // the bounds below hold from ~1000 on
    for (int round = 0; round < 4; ++round) {
        std::vector<Vec4> pos;
        for (int i = 0; i < 3 * count; ++i) {
            Vec4 p{wild(), wild(), wild(), wild()};
            switch (rng() % 6) {
                case 0: p.w = 0.0f; break;
                case 1: p.w = 1e-7f; break;
                case 2: p = Vec4{unit(rng), unit(rng), std::abs(unit(rng)), 1.0f}; break;  // on screen
                case 3: p.z = std::abs(p.w) * 0.5f; break;  // between near and far when w > 0
                default: break;
            }
            pos.push_back(p);
        }
        const Drawn d = draw_counting(pos, 128, 96, state_always(),
                                      {.threads = round % 2 ? 2 : 1, .tile_size = round % 2 ? 8 : 32});
        EXPECT_EQ(d.stats.triangles_in, static_cast<unsigned>(count));
        EXPECT_EQ(d.stats.triangles_invalid, 0u) << "all of them are finite";
        EXPECT_GT(d.stats.triangles_clipped, static_cast<unsigned>(count / 10));
        EXPECT_GT(d.stats.triangles_rasterized, static_cast<unsigned>(count / 50));
        EXPECT_EQ(d.bad_inputs, 0);
        EXPECT_TRUE(framebuffer_sane(d));
    }
}

// ---- (c) bad triangles in the same draw as a good one ---------------------------------------------

// The good triangle: exact fixed-point vertices on a 256 x 256 target, window depth 0.5.
const Rect k_vp{0, 0, 256, 256};
std::vector<Vec4> good_triangle() {
    return {R::clip_from_fixed({40 * 256 + 64, 30 * 256 + 128}, k_vp), R::clip_from_fixed({200 * 256 + 192, 60 * 256}, k_vp),
            R::clip_from_fixed({90 * 256 + 128, 220 * 256 + 32}, k_vp)};
}

struct BadTriangle {
    const char* what;
    Vec4 v[3];
    bool non_finite;  // counted as invalid
};

// Every one of these must render nothing: non-finite positions are rejected outright, and the others
// lie wholly outside one clip plane (behind the eye, past the far plane, beyond the guard band).
std::vector<BadTriangle> bad_triangles() {
    const Vec4 a{-0.9f, -0.9f, 0.5f, 1}, b{0.9f, -0.9f, 0.5f, 1}, c{0, 0.9f, 0.5f, 1};  // would cover the screen
    return {
        {"NaN x", {{k_nan, 0, 0.5f, 1}, b, c}, true},
        {"NaN w", {a, b, {0, 0, 0.5f, k_nan}}, true},
        {"+inf x", {a, {k_inf, 0, 0.5f, 1}, c}, true},
        {"-inf w", {a, b, {0, 0, 0.5f, -k_inf}}, true},
        {"inf z", {a, b, {0, 0, k_inf, 1}}, true},
        {"NaN, inf and a normal vertex", {{k_nan, k_nan, k_nan, k_nan}, {k_inf, -k_inf, 0, 1}, c}, true},
        {"all at 1e30, one side", {{1e30f, 0, 0.5f, 1}, {2e30f, 1e30f, 0.5f, 1}, {1.5e30f, -1e30f, 0.5f, 1}}, false},
        {"all at 1e38, one side", {{-1e38f, 3e38f, 0.5f, 1}, {-3e38f, -3e38f, 0.5f, 1}, {-2e38f, 0, 0.5f, 1}}, false},
        {"max float", {{0, 3.4e38f, 0.5f, 1}, {3.4e38f, 3.4e38f, 0.5f, 1}, {-3.4e38f, 3.4e38f, 0.5f, 1}}, false},
        {"w < 0 for all vertices", {{-0.5f, -0.5f, -0.5f, -1}, {0.5f, -0.5f, -0.5f, -1}, {0, 0.5f, -0.5f, -1}}, false},
        {"w < 0, mirror of a visible triangle", {{0.9f, 0.9f, -0.5f, -1}, {-0.9f, 0.9f, -0.5f, -1}, {0, -0.9f, -0.5f, -1}}, false},
        {"w = 0 for all vertices", {{1, 0, 0.5f, 0}, {0, 1, 0.5f, 0}, {-1, -1, 0.5f, 0}}, false},
        {"w = -0 and w < 0 mixed", {{0, 0, 0, -0.0f}, {1, 1, -0.5f, -1}, {-1, 1, -1, -2}}, false},
        {"w denormal", {{0, 0, 0, 1e-40f}, {1e-40f, 0, 0, 1e-40f}, {0, 1e-40f, 0, 1e-40f}}, false},
        {"1e30 and w < 0", {{1e30f, 1e30f, -1, -1}, {-1e30f, 0, -1, -1}, {0, -1e30f, -1, -1e30f}}, false},
        {"beyond the far plane", {{-0.9f, -0.9f, 2, 1}, {0.9f, -0.9f, 2, 1}, {0, 0.9f, 1.5f, 1}}, false},
    };
}

TEST(Clip, BadTrianglesDoNotDisturbAGoodOneInTheSameDraw) {
    DrawState state;  // defaults: back-face culling, depth less
    state.cull = CullMode::none;
    const std::vector<Vec4> good = good_triangle();
    const Drawn alone = draw_counting(good, 256, 256, state);
    ASSERT_EQ(alone.stats.triangles_rasterized, 1u);
    int covered = 0;
    for (int h : alone.hits) covered += h;
    ASSERT_GT(covered, 5000);

    const std::vector<BadTriangle> bad = bad_triangles();
    int non_finite = 0;
    for (const BadTriangle& t : bad) non_finite += t.non_finite;
    // The good triangle first, in the middle, last; and once among 600 copies of the bad ones (more
    // than one front-end chunk), with 1 and 2 threads.
    for (int repeat : {1, 40}) {
        for (int where = 0; where < 3; ++where) {
            std::vector<Vec4> pos;
            const std::size_t total = bad.size() * repeat;
            const std::size_t good_at = where == 0 ? 0 : (where == 1 ? total / 2 : total);
            std::size_t bad_triangles_in = 0;
            for (std::size_t i = 0; i <= total; ++i) {
                if (i == good_at) pos.insert(pos.end(), good.begin(), good.end());
                if (i == total) break;
                const BadTriangle& t = bad[i % bad.size()];
                pos.insert(pos.end(), t.v, t.v + 3);
                ++bad_triangles_in;
            }
            for (int threads : {1, 2}) {
                const Drawn d = draw_counting(pos, 256, 256, state, {.threads = threads, .tile_size = 16});
                SCOPED_TRACE(::testing::Message() << "repeat " << repeat << ", good at " << good_at << ", threads " << threads);
                EXPECT_TRUE(std::equal(d.fb.colour_data(), d.fb.colour_data() + 256 * 256, alone.fb.colour_data()));
                EXPECT_TRUE(std::equal(d.fb.depth_data(), d.fb.depth_data() + 256 * 256, alone.fb.depth_data()));
                EXPECT_EQ(d.hits, alone.hits);
                EXPECT_EQ(d.stats.triangles_in, bad_triangles_in + 1);
                EXPECT_EQ(d.stats.triangles_invalid, static_cast<std::uint64_t>(non_finite * repeat));
                EXPECT_EQ(d.stats.triangles_rasterized, 1u);
                EXPECT_EQ(d.stats.triangles_culled, 0u);
                EXPECT_EQ(d.bad_inputs, 0);
            }
        }
    }
    // And each bad triangle alone renders nothing.
    for (const BadTriangle& t : bad) {
        const Drawn d = draw_counting({t.v[0], t.v[1], t.v[2]}, 256, 256, state);
        EXPECT_TRUE(coverage_is(d, [](int, int) { return 0; })) << t.what;
        EXPECT_EQ(d.stats.triangles_invalid, t.non_finite ? 1u : 0u) << t.what;
        EXPECT_EQ(d.stats.triangles_rasterized, 0u) << t.what;
    }
}

// Finite coordinates at 1e30 .. 3e38 mixed with ordinary ones are real (if absurd) triangles: the
// clipper must compute their intersections without losing them. The triangle (0, 0), (M, 0), (0, M)
// in NDC is the quadrant x > 0, y > 0 for any huge M: its edges on the axes stay exact through
// clipping (interpolating between equal coordinates), and lie on pixel boundaries (x = 128, y = 128),
// so the expected coverage is exactly the top-right quarter of the target.
TEST(Clip, HugeButFiniteCoordinatesRenderTheirShape) {
    for (float m : {1e10f, 1e30f, 1e38f, 3e38f, std::numeric_limits<float>::max()}) {
        for (int winding = 0; winding < 2; ++winding) {
            std::vector<Vec4> pos = {{0, 0, 0.5f, 1}, {m, 0, 0.5f, 1}, {0, m, 0.5f, 1}};
            if (winding) std::swap(pos[1], pos[2]);
            const Drawn d = draw_counting(pos, 256, 256, state_always());
            EXPECT_TRUE(coverage_is(d, [](int x, int y) { return x >= 128 && y < 128 ? 1 : 0; })) << "M = " << m;
            EXPECT_EQ(d.stats.triangles_invalid, 0u) << "M = " << m;
            EXPECT_EQ(d.bad_inputs, 0);
            EXPECT_TRUE(framebuffer_sane(d));
        }
    }
    // Spanning -3e38 .. 3e38: differences of coordinates overflow float, yet the triangle is finite and
    // is the upper half-plane (y > 0 in NDC) as far as the viewport can tell: rows 0..127.
    for (int winding = 0; winding < 2; ++winding) {
        std::vector<Vec4> span = {{-3e38f, 0, 0.5f, 1}, {3e38f, 0, 0.5f, 1}, {0, 3e38f, 0.5f, 1}};
        if (winding) std::swap(span[1], span[2]);
        const Drawn d = draw_counting(span, 256, 256, state_always());
        EXPECT_TRUE(coverage_is(d, [](int, int y) { return y < 128 ? 1 : 0; }));
        EXPECT_EQ(d.stats.triangles_invalid, 0u);
        EXPECT_TRUE(framebuffer_sane(d));
    }
}

// A large world: a ground plane 2e6 units across, near plane at 0.01, eye 1 unit up looking level in
// several directions; every pixel ray below the horizon meets the ground within 1e6 units, so rows
// 128.. are ground (drawn once) and rows ..127 sky (the far boundary is at least 1e6 away: within
// 0.0002 px of the horizon). Clipping here pits w = 1e6 against w = 0.01: the near-plane and
// guard-band intersections must not lose w to cancellation (which would put them behind the eye and
// get the triangles dropped).
TEST(Clip, LargeWorldGroundPlaneWithACloseNearPlane) {
    const float L = 1e6f;
    for (float yaw : {0.0f, 0.3f, 0.7f, 1.1f, 2.0f, 3.0f}) {
        const Vec3 eye{0, 1, 0};
        const Mat4 clip_from_world = perspective_rh_zo(radians(90.0f), 1.0f, 0.01f, 1e8f) *
                                     look_at_rh(eye, eye + Vec3{std::sin(yaw), 0, -std::cos(yaw)}, {0, 1, 0});
        const Vec4 c[4] = {{-L, 0, -L, 1}, {L, 0, -L, 1}, {L, 0, L, 1}, {-L, 0, L, 1}};
        std::vector<Vec4> pos;
        for (int k : {0, 1, 2, 0, 2, 3}) pos.push_back(clip_from_world * c[k]);
        for (RendererConfig config : {RendererConfig{.threads = 1, .tile_size = 64}, RendererConfig{.threads = 2, .tile_size = 8}}) {
            const Drawn d = draw_counting(pos, 256, 256, state_always(), config);
            EXPECT_TRUE(coverage_is(d, [](int, int y) { return y >= 128 ? 1 : 0; })) << "yaw " << yaw;
            EXPECT_EQ(d.stats.triangles_invalid, 0u) << "yaw " << yaw;
            EXPECT_EQ(d.bad_inputs, 0);
            EXPECT_TRUE(framebuffer_sane(d));
        }
    }
}

// ---- (d) behind the eye, and through the eye plane -------------------------------------------------

const Mat4 k_projection = perspective_rh_zo(radians(90.0f), 1.0f, 0.1f, 100.0f);  // view = identity

TEST(Clip, TrianglesBehindTheEyeProduceNothing) {
    const Vec3 tris[][3] = {
        {{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}},            // straight behind
        {{-50, -50, 0.5f}, {50, -50, 0.5f}, {0, 50, 20}},  // behind, huge
        {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}},            // in the eye plane: w = 0
        {{-1, -1, -0.05f}, {1, -1, 0}, {0, 1, 3}},       // in front of the eye but before the near plane
        {{-1, -1, -0.0999f}, {1, -1, -0.05f}, {0, 1, 1}},
    };
    for (const auto& t : tris)
        for (int winding = 0; winding < 2; ++winding) {
            std::vector<Vec4> pos;
            for (int k : {0, winding ? 2 : 1, winding ? 1 : 2}) pos.push_back(k_projection * Vec4{t[k], 1});
            const Drawn d = draw_counting(pos, 256, 256, state_always());
            EXPECT_TRUE(coverage_is(d, [](int, int) { return 0; }));
            EXPECT_EQ(d.stats.triangles_rasterized, 0u);
            EXPECT_EQ(d.stats.triangles_invalid, 0u);
        }
}

// A triangle from a point level with the eye (w exactly 0) to two points 10 units ahead, 1 unit below:
// v0 = (0, -1, 0), v1 = (-1, -1, -10), v2 = (1, -1, -10) in view space. The edges from v0 project to
// the vertical lines ndc_x = -0.1 and +0.1 (every point (-s, -1, -10 s) projects to x = -1/10), and the
// far edge to ndc_y = -0.1; the near plane cuts it far below the screen (ndc_y = -10). So it covers
// exactly x in (115.2, 140.8), y > 140.8 in pixels: columns 115..140, rows 141..255. All boundaries are
// at least 0.2 px from any pixel centre, far more than float rounding can move them.
TEST(Clip, TriangleThroughTheEyePlaneWithAVertexAtWZero) {
    const Vec4 v[3] = {k_projection * Vec4{0, -1, 0, 1}, k_projection * Vec4{-1, -1, -10, 1}, k_projection * Vec4{1, -1, -10, 1}};
    ASSERT_EQ(v[0].w, 0.0f);
    for (int winding = 0; winding < 2; ++winding)
        for (RendererConfig config : {RendererConfig{.threads = 1, .tile_size = 8}, RendererConfig{.threads = 2, .tile_size = 64}}) {
            const std::vector<Vec4> pos = winding ? std::vector<Vec4>{v[0], v[2], v[1]} : std::vector<Vec4>{v[0], v[1], v[2]};
            const Drawn d = draw_counting(pos, 256, 256, state_always(), config);
            EXPECT_TRUE(coverage_is(d, [](int x, int y) { return x >= 115 && x <= 140 && y >= 141 ? 1 : 0; }));
            EXPECT_EQ(d.stats.triangles_clipped, 1u);
            EXPECT_EQ(d.stats.triangles_invalid, 0u);
            EXPECT_EQ(d.bad_inputs, 0);
            EXPECT_TRUE(framebuffer_sane(d));
        }
}

// ---- (e) across the guard band --------------------------------------------------------------------

// Vertices at +-1e6 in NDC (1.28e8 px away; the guard band is 8192 px): the triangle is clipped to the
// guard band and fanned, and what lands in the viewport is exactly the original triangle there.
TEST(Clip, TriangleContainingTheViewportCoversEveryPixelOnce) {
    const Vec4 a{-1e6f, -1e6f, 0.5f, 1}, b{1e6f, -1e6f, 0.5f, 1}, c{0, 1e6f, 0.5f, 1};
    for (const auto& pos : {std::vector<Vec4>{a, b, c}, std::vector<Vec4>{a, c, b}})
        for (RendererConfig config : {RendererConfig{.threads = 1, .tile_size = 8}, RendererConfig{.threads = 2, .tile_size = 32}}) {
            const Drawn d = draw_counting(pos, 256, 256, state_always(), config);
            EXPECT_TRUE(coverage_is(d, [](int, int) { return 1; }));
            EXPECT_EQ(d.stats.triangles_clipped, 1u);
            EXPECT_GE(d.stats.triangles_rasterized, 1u);
        }
}

// Edges that cross the viewport exactly on pixel boundaries or pixel centres, with all vertices far
// outside the guard band. Clipping interpolates between two vertices with the same y (or x), so those
// edges stay exact, and the top-left rule applies to them: a horizontal edge through the centres of
// row 63 (ndc_y = 1 - 2 * 63.5 / 256) keeps row 63 when the triangle is below it (a top edge) and
// drops it when the triangle is above (a bottom edge); likewise a vertical edge through the centres of
// column 100 keeps it only as a left edge.
TEST(Clip, GuardBandClippedEdgesKeepTheTopLeftRule) {
    const float e = 1e6f;
    const float on_boundary = 0.5f;                // sy = 64: between rows 63 and 64
    const float on_centre_row = 1.0f - 2.0f * 63.5f / 256.0f;  // sy = 63.5: centres of row 63
    const float on_centre_col = 2.0f * 100.5f / 256.0f - 1.0f;  // sx = 100.5: centres of column 100
    struct Case {
        const char* what;
        Vec4 v[3];
        int (*want)(int x, int y);
    };
    const Case cases[] = {
        {"above a row boundary", {{-e, on_boundary, 0.5f, 1}, {e, on_boundary, 0.5f, 1}, {0, e, 0.5f, 1}},
         [](int, int y) { return y <= 63 ? 1 : 0; }},
        {"below a row boundary", {{-e, on_boundary, 0.5f, 1}, {e, on_boundary, 0.5f, 1}, {0, -e, 0.5f, 1}},
         [](int, int y) { return y >= 64 ? 1 : 0; }},
        {"above centres: bottom edge", {{-e, on_centre_row, 0.5f, 1}, {e, on_centre_row, 0.5f, 1}, {0, e, 0.5f, 1}},
         [](int, int y) { return y <= 62 ? 1 : 0; }},
        {"below centres: top edge", {{-e, on_centre_row, 0.5f, 1}, {e, on_centre_row, 0.5f, 1}, {0, -e, 0.5f, 1}},
         [](int, int y) { return y >= 63 ? 1 : 0; }},
        {"right of centres: left edge", {{on_centre_col, -e, 0.5f, 1}, {on_centre_col, e, 0.5f, 1}, {e, 0, 0.5f, 1}},
         [](int x, int) { return x >= 100 ? 1 : 0; }},
        {"left of centres: right edge", {{on_centre_col, -e, 0.5f, 1}, {on_centre_col, e, 0.5f, 1}, {-e, 0, 0.5f, 1}},
         [](int x, int) { return x <= 99 ? 1 : 0; }},
    };
    for (const Case& c : cases)
        for (int winding = 0; winding < 2; ++winding) {
            const std::vector<Vec4> pos = winding ? std::vector<Vec4>{c.v[0], c.v[2], c.v[1]} : std::vector<Vec4>{c.v[0], c.v[1], c.v[2]};
            const Drawn d = draw_counting(pos, 256, 256, state_always());
            EXPECT_TRUE(coverage_is(d, c.want)) << c.what << ", winding " << winding;
            EXPECT_EQ(d.stats.triangles_clipped, 1u) << c.what;
        }
}

// Random triangles with vertices 1e4 .. 1e6 NDC away, edges crossing the viewport at arbitrary angles,
// against the analytic half-planes. Clipped vertices carry float rounding (~2e-3 px at the guard band,
// plus the 1/512 px of snapping), which tilts an edge by at most ~0.005 px across the viewport; pixels
// whose centre is within 0.02 px of an edge line are not decided. Every other pixel is exact.
TEST(Clip, RandomGuardBandTrianglesMatchTheirHalfPlanes) {
    std::mt19937_64 rng(32);
    std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979323846), magnitude(4.0, 6.0), offset(-1.2, 1.2);
    int decided_in = 0, decided_out = 0;
    for (int n = 0; n < 200; ++n) {
        // Three vertices far away in random directions, shifted so that edges cross the viewport.
        Vec4 v[3];
        const double sx = offset(rng), sy = offset(rng);
        for (Vec4& p : v) {
            const double r = std::pow(10.0, magnitude(rng)), t = angle(rng);
            p = Vec4{static_cast<float>(sx + r * std::cos(t)), static_cast<float>(sy + r * std::sin(t)), 0.5f, 1};
        }
        // Screen-space (pixels, y down) copies in double, exactly as the floats are.
        double px[3], py[3];
        for (int k = 0; k < 3; ++k) px[k] = 128.0 + 128.0 * v[k].x, py[k] = 128.0 - 128.0 * v[k].y;
        const double area = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
        if (std::abs(area) < 1.0) continue;
        const auto want = [&](int x, int y) {
            bool inside = true;
            for (int e = 0; e < 3; ++e) {
                const int a = e, b = (e + 1) % 3;
                const double dx = px[b] - px[a], dy = py[b] - py[a];
                const double dist = ((x + 0.5 - px[a]) * dy - (y + 0.5 - py[a]) * dx) / std::hypot(dx, dy) * (area > 0 ? -1 : 1);
                if (std::abs(dist) < 0.02) return -1;
                inside = inside && dist > 0;
            }
            return inside ? 1 : 0;
        };
        const Drawn d = draw_counting({v[0], v[1], v[2]}, 256, 256, state_always(),
                                      {.threads = 1 + n % 2, .tile_size = n % 3 == 0 ? 8 : 64});
        ASSERT_TRUE(coverage_is(d, want)) << "triangle " << n << ": (" << v[0].x << ", " << v[0].y << "), (" << v[1].x
                                          << ", " << v[1].y << "), (" << v[2].x << ", " << v[2].y << ")";
        for (int y = 0; y < 256; ++y)
            for (int x = 0; x < 256; ++x) {
                const int w = want(x, y);
                decided_in += w == 1;
                decided_out += w == 0;
            }
    }
    EXPECT_GT(decided_in, 2'000'000);  // the half-planes really do cut through the viewport
    EXPECT_GT(decided_out, 2'000'000);
}

// ---- (f) perspective-correct varyings, screen-linear depth -------------------------------------

// A quad tilted in depth, from exact fixed-point screen positions with w = 4 at the far (top) edge and
// w = 1 at the near (bottom) edge. The definition: with screen-space barycentrics l_i of the pixel
// centre (exact, in double), a varying is (sum l_i u_i / w_i) / (sum l_i / w_i), and window depth is
// sum l_i z_i. The renderer evaluates these with float planes; relative float error per operation is
// 6e-8 and the chain (planes relative to vertex 0, the divide by q) has about a dozen operations with
// values of order 1 (u, v, depth in [0, 1], w <= 4), so 2e-6 absolute leaves a wide margin while
// still being 25000 times smaller than the difference to screen-linear interpolation (> 0.05 here).
TEST(Clip, PerspectiveCorrectVaryingsAndScreenLinearDepth) {
    const int W = 256, H = 256;
    const R::Fixed s[4] = {{60 * 256 + 128, 30 * 256 + 64}, {196 * 256 + 128, 30 * 256 + 64},
                           {240 * 256 + 64, 230 * 256 + 192}, {16 * 256 + 192, 230 * 256 + 192}};
    const float w[4] = {4, 4, 1, 1}, z[4] = {0.9f, 0.9f, 0.2f, 0.2f};
    const Vec3 uv[4] = {{0, 0, 0.25f}, {1, 0, 0.5f}, {1, 1, 0.75f}, {0, 1, 1.0f}};
    std::vector<Vec4> pos;
    std::vector<Vec3> var;
    const int tri_vertices[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (const auto& t : tri_vertices)
        for (int k : t) {
            ASSERT_TRUE(R::snaps_exactly(s[k], k_vp, z[k], w[k]));
            pos.push_back(R::clip_from_fixed(s[k], k_vp, z[k], w[k]));
            var.push_back(uv[k]);
        }
    // Record what the fragment stage receives at each pixel.
    std::vector<Vec3> got_v(W * H);
    std::vector<float> got_depth(W * H, -1);
    const auto shader = make_shader<3>(
        [&](std::uint32_t i, Varyings<3>& out) {
            out.set(0, var[i]);
            return pos[i];
        },
        [&](const FragmentIn<3>& in) {
            const std::size_t i = static_cast<std::size_t>(in.pos_screen.y) * W + static_cast<std::size_t>(in.pos_screen.x);
            got_v[i] = in.v.vec3(0);
            got_depth[i] = in.depth;
            return Vec4{1, 1, 1, 1};
        });
    Framebuffer fb(W, H);
    fb.clear(Vec4{0, 0, 0, 0}, 1.0f);
    Renderer({.threads = 2, .tile_size = 16}).draw(fb, state_always(), DrawInput{6, {}}, shader);

    double max_err_v = 0, max_err_depth = 0, max_linear_diff = 0;
    int checked = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const R::Fixed p = R::pixel_centre(x, y);
            int tri = -1;
            for (int t = 0; t < 2; ++t) {
                const R::Fixed v[3] = {s[tri_vertices[t][0]], s[tri_vertices[t][1]], s[tri_vertices[t][2]]};
                if (R::covers(v, p)) tri = t;
            }
            const std::size_t i = static_cast<std::size_t>(y) * W + x;
            if (tri < 0) {
                EXPECT_EQ(got_depth[i], -1.0f) << "drawn outside the quad at " << x << "," << y;
                continue;
            }
            ASSERT_GE(got_depth[i], 0.0f) << "not drawn inside the quad at " << x << "," << y;
            const int* k = tri_vertices[tri];
            const double area = static_cast<double>(R::signed_area2(s[k[0]], s[k[1]], s[k[2]]));
            double l[3];
            for (int e = 0; e < 3; ++e)
                l[e] = static_cast<double>(R::signed_area2(p, s[k[(e + 1) % 3]], s[k[(e + 2) % 3]])) / area;
            double denom = 0, depth = 0;
            for (int e = 0; e < 3; ++e) denom += l[e] / w[k[e]], depth += l[e] * z[k[e]];
            for (int c = 0; c < 3; ++c) {
                double num = 0, linear = 0;
                for (int e = 0; e < 3; ++e) num += l[e] * uv[k[e]][c] / w[k[e]], linear += l[e] * uv[k[e]][c];
                max_err_v = std::max(max_err_v, std::abs(num / denom - got_v[i][c]));
                max_linear_diff = std::max(max_linear_diff, std::abs(num / denom - linear));
            }
            max_err_depth = std::max(max_err_depth, std::abs(depth - got_depth[i]));
            EXPECT_EQ(fb.depth(x, y), got_depth[i]);
            ++checked;
        }
    EXPECT_GT(checked, 30000);
    EXPECT_LT(max_err_v, 2e-6);
    EXPECT_LT(max_err_depth, 2e-6);
    EXPECT_GT(max_linear_diff, 0.05) << "the test must be able to tell perspective-correct from linear";
}

// The same property from a camera: a 2 x 2 square on the ground, 1 to 5 units ahead, with u along x and
// v along z. The exact value at a pixel is found by casting the ray through the pixel centre onto the
// plane (in double). The renderer interpolates over the projected vertices snapped to 1/256 px, each
// moved by at most d = sqrt(2) / 512 px (plus float projection error, far below 1%). Moving the
// vertices by d_i warps the screen-linear planes 1/w and u/w by the same affine map, p -> p - sum l_i d_i
// to first order (l_i the screen barycentrics), so the value at p changes by at most |grad u(p)| * d.
// Tolerance per pixel: |grad u(p)| * 1.01 d + 2e-6 (the float error measured exactly in the test above).
TEST(Clip, PerspectiveCorrectVaryingsFromACamera) {
    const int W = 256, H = 256;
    const Vec3 eye{0, 1, 0};
    const Mat4 clip_from_world = perspective_rh_zo(radians(60.0f), 1.0f, 0.1f, 100.0f) * look_at_rh(eye, {0, 0, -3}, {0, 1, 0});
    const Vec3 corner[4] = {{-1, 0, -5}, {1, 0, -5}, {1, 0, -1}, {-1, 0, -1}};
    std::vector<Vec4> pos;
    std::vector<Vec3> var;
    for (int k : {0, 1, 2, 0, 2, 3}) {
        pos.push_back(clip_from_world * Vec4{corner[k], 1});
        var.push_back({(corner[k].x + 1) / 2, (corner[k].z + 5) / 4, 0});
    }
    std::vector<Vec3> got(W * H);
    std::vector<std::uint8_t> drawn(W * H, 0);
    const auto shader = make_shader<3>(
        [&](std::uint32_t i, Varyings<3>& out) {
            out.set(0, var[i]);
            return pos[i];
        },
        [&](const FragmentIn<3>& in) {
            const std::size_t i = static_cast<std::size_t>(in.pos_screen.y) * W + static_cast<std::size_t>(in.pos_screen.x);
            got[i] = in.v.vec3(0);
            drawn[i] = 1;
            return Vec4{1, 1, 1, 1};
        });
    Framebuffer fb(W, H);
    Renderer({.threads = 2, .tile_size = 32}).draw(fb, state_always(), DrawInput{6, {}}, shader);

    // Camera basis in double: forward F, right R, up U; the ray through screen point (sx, sy) is
    // F + nx tan(30) R + ny tan(30) U, and it meets the ground (eye 1 unit above it) at t = -1 / ray.y.
    const double fl = std::sqrt(10.0);
    const double F[3] = {0, -1 / fl, -3 / fl}, Rr[3] = {1, 0, 0}, U[3] = {0, 3 / fl, -1 / fl};
    const double t30 = std::tan(3.14159265358979323846 / 6);
    const auto exact = [&](double sx, double sy, double& u, double& v) {
        const double nx = sx / 128.0 - 1.0, ny = 1.0 - sy / 128.0;
        double d[3];
        for (int c = 0; c < 3; ++c) d[c] = F[c] + nx * t30 * Rr[c] + ny * t30 * U[c];
        const double t = -1.0 / d[1];
        u = (t * d[0] + 1) / 2;
        v = (t * d[2] + 5) / 4;
    };
    const double snap = 1.01 * std::sqrt(2.0) / 512, h = 1e-3;
    double worst = 0;  // largest error as a fraction of its tolerance
    int checked = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * W + x;
            if (!drawn[i]) continue;
            double u, v, ux0, vx0, ux1, vx1, uy0, vy0, uy1, vy1;
            exact(x + 0.5, y + 0.5, u, v);
            exact(x + 0.5 - h, y + 0.5, ux0, vx0);
            exact(x + 0.5 + h, y + 0.5, ux1, vx1);
            exact(x + 0.5, y + 0.5 - h, uy0, vy0);
            exact(x + 0.5, y + 0.5 + h, uy1, vy1);
            const double tol_u = std::hypot(ux1 - ux0, uy1 - uy0) / (2 * h) * snap + 2e-6;
            const double tol_v = std::hypot(vx1 - vx0, vy1 - vy0) / (2 * h) * snap + 2e-6;
            ASSERT_NEAR(got[i].x, u, tol_u) << "u at " << x << "," << y;
            ASSERT_NEAR(got[i].y, v, tol_v) << "v at " << x << "," << y;
            worst = std::max({worst, std::abs(got[i].x - u) / tol_u, std::abs(got[i].y - v) / tol_v});
            ++checked;
        }
    EXPECT_GT(checked, 20000);
    EXPECT_GT(worst, 0.01) << "the comparison is not vacuous";
}

// The built-in shaders' compiled vertex stage keeps no array of clip positions: clipping recomputes
// those of the triangles it cuts (ClipVertices::recompute). A ground grid through the near plane and
// past the guard band, drawn by Lambert and by a type derived from it (which takes vertex() per vertex
// and keeps the positions), gives the same bytes; one clipped triangle has corners in the first and
// the last of the vertex stage's blocks.
template <class S>
struct ByVertex : S {};

TEST(Clip, CompiledVertexStageClipsWhatVertexClips) {
    const int W = 160, H = 120, n = 96;  // n x n vertices: more than one vertex block (4,096)
    Mesh mesh;
    std::mt19937 rng(2026112712);
    std::uniform_real_distribution<float> tilt(-0.4f, 0.4f), unit(0.0f, 1.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // x far past the guard band at the sides, z from behind the eye to the distance.
            mesh.positions.push_back({(i - n / 2) * 400.0f, unit(rng) * 0.2f, 40.0f - j * 2.0f});
            mesh.normals.push_back(normalize(Vec3{tilt(rng), 1.0f, tilt(rng)}));
            mesh.colours.push_back({unit(rng), unit(rng), unit(rng), 1.0f});
        }
    const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * n + i); };
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i)
            for (std::uint32_t k : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)})
                mesh.indices.push_back(k);
    // A triangle from the first row to the last: its corners in the first and the last vertex block.
    for (std::uint32_t k : {at(n / 2, 0), at(n / 2 + 1, 0), at(n / 2, n - 1)}) mesh.indices.push_back(k);
    const Vec3 eye{0, 1.5f, 0};
    ShadingUniforms u;
    u.clip_from_object = perspective_rh_zo(radians(70.0f), static_cast<float>(W) / H, 0.1f, 150.0f) *
                         look_at_rh(eye, eye + Vec3{0, -0.3f, -1}, {0, 1, 0});
    u.key = DirectionalLight{normalize(Vec3{0.3f, 1.0f, 0.2f}), {1, 1, 1}};
    const DrawInput input{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices};
    const auto draw = [&](const auto& shader, DrawStats& stats) {
        Framebuffer fb(W, H);
        fb.clear(Vec4{0, 0, 0, 1}, 1.0f);
        stats = Renderer({.threads = 2, .tile_size = 16}).draw(fb, DrawState{}, input, shader);
        return fb;
    };
    const MeshArrays arrays = MeshArrays::of(mesh);
    const auto compare = [&](const auto& compiled, const auto& by_vertex) {
        DrawStats a, b;
        const Framebuffer fa = draw(compiled, a), fb = draw(by_vertex, b);
        EXPECT_GT(a.triangles_clipped, 300u);
        EXPECT_EQ(a.triangles_clipped, b.triangles_clipped);
        EXPECT_EQ(a.triangles_rasterized, b.triangles_rasterized);
        int drawn = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                ASSERT_EQ(fa.colour(x, y), fb.colour(x, y)) << x << "," << y;
                ASSERT_EQ(std::memcmp(&fa.depth_data()[y * W + x], &fb.depth_data()[y * W + x], sizeof(float)), 0) << x << "," << y;
                drawn += fa.depth(x, y) < 1.0f;
            }
        EXPECT_GT(drawn, W * H / 3);
    };
    compare(shaders::Lambert{arrays, u}, ByVertex<shaders::Lambert>{{arrays, u}});
    compare(shaders::LambertBaseColour{arrays, u}, ByVertex<shaders::LambertBaseColour>{{arrays, u}});
}

}  // namespace
