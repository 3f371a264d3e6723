// Property: the renderer's coverage is exactly the reference rasterizer's (tests/support/
// reference_raster.*), pixel for pixel, for tens of thousands of random grid-snapped triangles of every
// awkward kind, both windings, several tile sizes, thread counts, target sizes and viewports.
//
// Vertices are generated directly in 1/256-pixel fixed point and turned into clip-space positions
// that the renderer projects back onto exactly those fixed-point positions (clip_from_fixed with
// power-of-two viewports and w = 1, verified by snaps_exactly), so both sides see the same triangle
// and any difference is a coverage difference. All triangles stay inside the guard band (up to
// exactly 8192 px from the viewport centre, inclusive), where the renderer rasterizes without clipping.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "facet/renderer.hpp"
#include "support/reference_raster.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace R = facet_test::raster;

struct Target {
    int width, height;  // framebuffer
    Rect viewport;      // power-of-two width and height, so that clip_from_fixed is exact
};

R::Box scissor_of(const Target& t) {
    return {std::max(t.viewport.x, 0), std::max(t.viewport.y, 0), std::min(t.viewport.x + t.viewport.width, t.width),
            std::min(t.viewport.y + t.viewport.height, t.height)};
}

std::string describe(const R::Fixed (&v)[3]) {
    std::ostringstream s;
    for (int k = 0; k < 3; ++k)
        s << (k ? ", " : "") << "(" << v[k].x << "/256, " << v[k].y << "/256)";
    return s.str();
}

// Draws single triangles with a shader that paints every covered pixel white, and reads the
// coverage back (then clears the target for the next triangle).
class OneTriangle {
public:
    OneTriangle(RendererConfig config, Target target)
        : renderer_(config), fb_(target.width, target.height), target_(target) {
        fb_.clear(Vec4{0, 0, 0, 0});
    }

    DrawStats draw(const R::Fixed (&v)[3]) {
        for (int k = 0; k < 3; ++k) pos_[k] = R::clip_from_fixed(v[k], target_.viewport);
        DrawState state;
        state.cull = CullMode::none;
        state.depth_test = DepthTest::always;
        state.viewport = target_.viewport;
        const auto shader = make_shader<0>([this](std::uint32_t i, Varyings<0>&) { return pos_[i]; },
                                           [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
        return renderer_.draw(fb_, state, DrawInput{3, {}}, shader);
    }

    R::Mask take() {
        R::Mask mask(static_cast<std::size_t>(fb_.width()) * fb_.height());
        const Rgba8* c = fb_.colour_data();
        for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = c[i].r != 0;
        fb_.clear_colour(Vec4{0, 0, 0, 0});
        return mask;
    }

private:
    Renderer renderer_;
    Framebuffer fb_;
    Target target_;
    Vec4 pos_[3];
};

// ---- random triangles of every awkward kind -----------------------------------------------------

enum class Kind { tiny, normal, huge, sliver, axis_edges_on_centres, vertices_on_centres, off_screen, near_centres };
constexpr int k_kind_count = 8;
const char* kind_name(Kind k) {
    static const char* names[] = {"tiny", "normal", "huge", "sliver", "axis-edges-on-centres", "vertices-on-centres",
                                  "off-screen", "near-centres"};
    return names[static_cast<int>(k)];
}

class TriangleGen {
public:
    // `visible`: the pixels that can be covered (viewport within the target); `vp`: the viewport,
    // whose centre the guard band is measured from.
    TriangleGen(std::uint64_t seed, const Rect& vp, R::Box visible)
        : rng_(seed),
          x0_(std::int64_t{visible.x0} * R::k_sub), y0_(std::int64_t{visible.y0} * R::k_sub),
          x1_(std::int64_t{visible.x1} * R::k_sub), y1_(std::int64_t{visible.y1} * R::k_sub),
          w_(visible.x1 - visible.x0), h_(visible.y1 - visible.y0), vx_(visible.x0), vy_(visible.y0),
          cx_((2 * std::int64_t{vp.x} + vp.width) * R::k_sub / 2), cy_((2 * std::int64_t{vp.y} + vp.height) * R::k_sub / 2) {}

    void make(Kind kind, R::Fixed (&v)[3]) {
        const std::int64_t px = R::k_sub;
        switch (kind) {
            case Kind::tiny: {  // sub-pixel to 3 px, anywhere on or just off the viewport
                const R::Fixed base = point(x0_ - 8 * px, x1_ + 8 * px, y0_ - 8 * px, y1_ + 8 * px);
                const std::int64_t span = coin() ? px : 3 * px;
                v[0] = base;
                v[1] = {base.x + uni(-span, span), base.y + uni(-span, span)};
                v[2] = {base.x + uni(-span, span), base.y + uni(-span, span)};
                break;
            }
            case Kind::normal:
                for (auto& p : v) p = point(x0_ - 32 * px, x1_ + 32 * px, y0_ - 32 * px, y1_ + 32 * px);
                break;
            case Kind::huge: {  // up to 8000 px from the viewport centre: inside the 8192 px guard band
                const std::int64_t g = 8000 * px;
                for (auto& p : v) p = point(cx_ - g, cx_ + g, cy_ - g, cy_ + g);
                if (coin()) v[0] = point(x0_, x1_, y0_, y1_);  // one corner on screen
                if (uni(0, 3) == 0) {  // a vertex exactly on the guard band (inclusive: still not clipped)
                    const std::int64_t edge = std::int64_t{8192} * px;
                    v[1].x = coin() ? cx_ + edge : cx_ - edge;
                    if (coin()) v[2].y = coin() ? cy_ + edge : cy_ - edge;
                }
                break;
            }
            case Kind::sliver: {
                const R::Fixed p0 = point(x0_ - 16 * px, x1_ + 16 * px, y0_ - 16 * px, y1_ + 16 * px);
                if (coin()) {  // nearly collinear through rounding: third vertex near the segment
                    const std::int64_t reach = coin() ? 600 * px : 3000 * px;
                    const R::Fixed p1{p0.x + uni(-reach, reach), p0.y + uni(-reach, reach)};
                    const double t = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
                    const R::Fixed on{p0.x + std::llround(t * static_cast<double>(p1.x - p0.x)),
                                      p0.y + std::llround(t * static_cast<double>(p1.y - p0.y))};
                    v[0] = p0, v[1] = p1, v[2] = {on.x + uni(-2, 2), on.y + uni(-2, 2)};
                } else {  // exactly collinear along a small integer direction, or off it by one unit
                    const R::Fixed d{uni(-40, 40), uni(-40, 40)};
                    const std::int64_t m = uni(50, 3000), k = uni(1, m - 1);
                    const int nudge = static_cast<int>(uni(0, 4));
                    v[0] = p0;
                    v[1] = {p0.x + m * d.x, p0.y + m * d.y};
                    v[2] = {p0.x + k * d.x + (nudge == 1) - (nudge == 2), p0.y + k * d.y + (nudge == 3) - (nudge == 4)};
                }
                break;
            }
            case Kind::axis_edges_on_centres: {  // horizontal and vertical edges through pixel centres
                const std::int64_t i0 = vx_ + uni(-4, w_ + 4), j0 = vy_ + uni(-4, h_ + 4);
                const std::int64_t range = coin() ? 8 : std::max(w_, h_);
                const std::int64_t i1 = i0 + nonzero(range), j1 = j0 + nonzero(range);
                const R::Fixed a = centre(i0, j0), b = centre(i1, j0), c = centre(i0, j1);
                switch (uni(0, 3)) {
                    case 0: v[0] = a, v[1] = b, v[2] = c; break;                        // right angle at a
                    case 1: v[0] = a, v[1] = b, v[2] = {c.x + uni(-3 * px, 3 * px), c.y}; break;  // horizontal edge ab
                    case 2: v[0] = a, v[1] = c, v[2] = {b.x, b.y + uni(-3 * px, 3 * px)}; break;  // vertical edge ac
                    default: v[0] = b, v[1] = c, v[2] = {b.x, c.y}; break;              // right angle at (i1, j1)
                }
                break;
            }
            case Kind::vertices_on_centres: {
                const std::int64_t i = vx_ + uni(-2, w_ + 2), j = vy_ + uni(-2, h_ + 2);
                const std::int64_t r = coin() ? 6 : 60;
                v[0] = centre(i, j);
                v[1] = centre(i + uni(-r, r), j + uni(-r, r));
                v[2] = centre(i + uni(-r, r), j + uni(-r, r));
                break;
            }
            case Kind::off_screen: {
                const std::int64_t ew = std::int64_t{w_} * px, eh = std::int64_t{h_} * px;
                for (auto& p : v) p = point(x0_ - ew, x1_ + ew, y0_ - eh, y1_ + eh);
                switch (uni(0, 3)) {  // wholly off one side, just touching distance away
                    case 0: for (auto& p : v) p.x = x0_ - std::abs(p.x - x0_) % (2 * px); break;
                    case 1: for (auto& p : v) p.y = y1_ + std::abs(p.y - y1_) % (2 * px); break;
                    default: break;  // partly off-screen
                }
                break;
            }
            case Kind::near_centres: {  // coordinates on, or one unit beside, centres and pixel corners
                for (auto& p : v) {
                    const std::int64_t i = vx_ + uni(-2, w_ + 2), j = vy_ + uni(-2, h_ + 2);
                    const std::int64_t bx = coin() ? px / 2 : 0, by = coin() ? px / 2 : 0;
                    p = {std::int64_t{i} * px + bx + uni(-1, 1), std::int64_t{j} * px + by + uni(-1, 1)};
                    if (coin()) p = {v[0].x + (p.x - v[0].x) % (12 * px), v[0].y + (p.y - v[0].y) % (12 * px)};
                }
                break;
            }
        }
    }

private:
    std::int64_t uni(std::int64_t lo, std::int64_t hi) { return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_); }
    std::int64_t nonzero(std::int64_t r) {
        const std::int64_t v = uni(1, r);
        return coin() ? v : -v;
    }
    bool coin() { return (rng_() & 1) != 0; }
    R::Fixed point(std::int64_t xl, std::int64_t xh, std::int64_t yl, std::int64_t yh) { return {uni(xl, xh), uni(yl, yh)}; }
    static R::Fixed centre(std::int64_t i, std::int64_t j) { return R::pixel_centre(i, j); }

    std::mt19937_64 rng_;
    std::int64_t x0_, y0_, x1_, y1_;
    int w_, h_, vx_, vy_;
    std::int64_t cx_, cy_;
};

// ---- the property ---------------------------------------------------------------------------------

struct RasterCase {
    int tile_size, threads;
    Target target;
    std::uint64_t seed;
    const char* name;
};

void PrintTo(const RasterCase& c, std::ostream* os) { *os << c.name; }

class RasterReference : public ::testing::TestWithParam<RasterCase> {};

// x 6 cases = 30,000 triangles, each drawn in 2 windings (fewer under the sanitizers: sweep_size).
const int k_triangles_per_case = facet_test::sweep_size(5000);

TEST_P(RasterReference, RandomTrianglesMatchTheReferenceExactly) {
    const RasterCase& c = GetParam();
    const Target& target = c.target;
    const R::Box box = scissor_of(target);
    OneTriangle drawer({.threads = c.threads, .tile_size = c.tile_size}, target);
    TriangleGen gen(c.seed, target.viewport, box);
    std::mt19937_64 order_rng(c.seed ^ 0x5eed);

    int failures = 0, covered_triangles = 0, degenerate = 0;
    std::uint64_t covered_pixels = 0;
    int per_kind_covering[k_kind_count] = {};
    for (int n = 0; n < k_triangles_per_case && failures < 10; ++n) {
        const Kind kind = static_cast<Kind>(n % k_kind_count);
        R::Fixed v[3];
        gen.make(kind, v);
        for (const R::Fixed& p : v)
            ASSERT_TRUE(R::snaps_exactly(p, target.viewport)) << "generator left the exact range: " << describe(v);

        const R::Mask expected = R::rasterize(v, target.width, target.height, box);
        const auto expected_count = static_cast<std::uint64_t>(std::count(expected.begin(), expected.end(), 1));
        const bool zero_area = R::signed_area2(v[0], v[1], v[2]) == 0;
        degenerate += zero_area;
        if (expected_count > 0) {
            ++covered_triangles;
            ++per_kind_covering[n % k_kind_count];
        }
        covered_pixels += expected_count;

        // Both windings, each starting from a random vertex.
        const int r = static_cast<int>(order_rng() % 3);
        const R::Fixed windings[2][3] = {{v[r], v[(r + 1) % 3], v[(r + 2) % 3]}, {v[r], v[(r + 2) % 3], v[(r + 1) % 3]}};
        for (const auto& tri : windings) {
            const DrawStats stats = drawer.draw(tri);
            const R::Mask got = drawer.take();
            EXPECT_EQ(stats.triangles_in, 1u);
            EXPECT_EQ(stats.triangles_invalid, 0u);
            EXPECT_EQ(stats.triangles_clipped, 0u) << "inside the guard band nothing is clipped: " << describe(tri);
            EXPECT_EQ(stats.triangles_culled, zero_area ? 1u : 0u) << describe(tri);
            if (expected_count > 0) {
                EXPECT_EQ(stats.triangles_rasterized, 1u) << describe(tri);
            }
            if (got == expected) continue;
            ++failures;
            std::ostringstream diff;
            int shown = 0;
            for (int y = 0; y < target.height && shown < 8; ++y)
                for (int x = 0; x < target.width && shown < 8; ++x) {
                    const std::size_t i = static_cast<std::size_t>(y) * target.width + x;
                    if (got[i] != expected[i]) {
                        diff << " (" << x << "," << y << "): got " << int{got[i]} << " want " << int{expected[i]} << ";";
                        ++shown;
                    }
                }
            ADD_FAILURE() << kind_name(kind) << " triangle " << describe(tri) << " differs from the reference:"
                          << diff.str();
        }
    }
    // The generator must actually exercise the rasterizer: most triangles cover something, every
    // kind contributes, and some degenerate ones are in the mix (the counts for 5000 triangles,
    // scaled down with a smaller sweep).
    const double share = k_triangles_per_case / 5000.0;
    EXPECT_GT(covered_triangles, k_triangles_per_case / 2);
    for (int k = 0; k < k_kind_count; ++k)
        EXPECT_GT(per_kind_covering[k], 20 * share) << kind_name(static_cast<Kind>(k));
    EXPECT_GT(degenerate, 5 * share);
    EXPECT_GT(static_cast<double>(covered_pixels), 1'000'000 * share);
}

INSTANTIATE_TEST_SUITE_P(
    Configs, RasterReference,
    ::testing::Values(
        RasterCase{8, 1, {256, 256, {0, 0, 256, 256}}, 101, "tile8_threads1_256"},
        RasterCase{8, 2, {229, 151, {0, 0, 256, 256}}, 102, "tile8_threads2_partial_tiles"},
        RasterCase{16, 1, {300, 280, {16, 8, 256, 256}}, 103, "tile16_threads1_offset_viewport"},
        RasterCase{16, 2, {512, 128, {0, 0, 512, 128}}, 104, "tile16_threads2_wide"},
        RasterCase{64, 1, {229, 151, {0, 0, 256, 256}}, 105, "tile64_threads1_partial_tiles"},
        RasterCase{64, 2, {256, 256, {0, 0, 256, 256}}, 106, "tile64_threads2_256"}),
    [](const ::testing::TestParamInfo<RasterCase>& info) { return std::string(info.param.name); });

// ---- the support code itself ----------------------------------------------------------------------

// The fixed-point -> clip-space helper is exact over the whole range the tests use: pixel centres,
// pixel corners and arbitrary sub-pixel positions, out to the guard band, for every viewport above.
TEST(ReferenceRaster, ClipFromFixedRoundTripIsExact) {
    const Rect viewports[] = {{0, 0, 256, 256}, {16, 8, 256, 256}, {0, 0, 512, 128}, {0, 0, 512, 512}};
    std::mt19937_64 rng(7);
    for (const Rect& vp : viewports) {
        const std::int64_t cx = (2 * std::int64_t{vp.x} + vp.width) * R::k_sub / 2;
        const std::int64_t cy = (2 * std::int64_t{vp.y} + vp.height) * R::k_sub / 2;
        const std::int64_t g = 8000 * R::k_sub;
        std::vector<R::Fixed> points = {{cx - g, cy - g}, {cx + g, cy + g}, {cx - g, cy + g}, {0, 0}, {1, 1},
                                        {-1, -1},         {128, 128},       {cx, cy}};
        std::uniform_int_distribution<std::int64_t> d(-g, g);
        for (int i = 0; i < 20000; ++i) points.push_back({cx + d(rng), cy + d(rng)});
        for (const R::Fixed& p : points) {
            ASSERT_TRUE(R::snaps_exactly(p, vp)) << p.x << ", " << p.y;
            for (float w : {0.5f, 2.0f, 4.0f}) ASSERT_TRUE(R::snaps_exactly(p, vp, 0.5f, w)) << p.x << ", " << p.y;
        }
    }
    // The check can fail: with w = 1.1 the clip coordinates themselves are rounded.
    int inexact = 0;
    for (std::int64_t x = 1; x < 200; ++x) inexact += !R::snaps_exactly({x * 3701 + 5, 3}, {0, 0, 256, 256}, 0.5f, 1.1f);
    EXPECT_GT(inexact, 100);
}

// Hand-derived coverage: the reference implements the rule, not something that merely agrees with
// the renderer.
TEST(ReferenceRaster, HandComputedTriangles) {
    // Right triangle with legs on the centre row 0 and centre column 0, hypotenuse through centres
    // with i + j = 4. The top edge (row 0) and left edge (column 0) are in, the hypotenuse is a right
    // edge and is out: exactly the 10 centres with i, j >= 0 and i + j <= 3.
    const R::Fixed a = R::pixel_centre(0, 0), b = R::pixel_centre(4, 0), c = R::pixel_centre(0, 4);
    for (const auto& tri : {std::array{a, b, c}, std::array{a, c, b}, std::array{c, a, b}}) {
        const R::Fixed v[3] = {tri[0], tri[1], tri[2]};
        for (int j = -1; j < 6; ++j)
            for (int i = -1; i < 6; ++i)
                EXPECT_EQ(R::covers(v, R::pixel_centre(i, j)), i >= 0 && j >= 0 && i + j <= 3) << i << "," << j;
    }
    // Mirror image: legs on row 4 (bottom edge, out) and column 4 (right edge, out); hypotenuse
    // i + j = 4 is now a left/top-facing edge (interior to its right) and is in.
    const R::Fixed d = R::pixel_centre(4, 4);
    const R::Fixed m[3] = {d, b, c};
    for (int j = -1; j < 6; ++j)
        for (int i = -1; i < 6; ++i)
            EXPECT_EQ(R::covers(m, R::pixel_centre(i, j)), i <= 3 && j <= 3 && i + j >= 4) << i << "," << j;
    // Zero area covers nothing, even its own vertices' pixel centres.
    const R::Fixed flat[3] = {a, b, R::pixel_centre(2, 0)};
    for (int i = -1; i < 6; ++i) EXPECT_FALSE(R::covers(flat, R::pixel_centre(i, 0)));
}

// The two independent support algorithms agree: the per-triangle rule summed over a fan equals the
// scanline polygon rule, and no pixel is counted twice. (This is the watertightness argument made
// concrete on the reference side.)
TEST(ReferenceRaster, TriangleRuleSummedOverAFanEqualsPolygonRule) {
    std::mt19937_64 rng(11);
    const int w = 96, h = 96;
    for (int round = 0; round < 20; ++round) {
        std::uniform_int_distribution<std::int64_t> jitter(-400, 400);
        const bool on_centre = round % 2 == 0;
        const R::Fixed centre = on_centre ? R::pixel_centre(48, 48) : R::Fixed{48 * 256 + jitter(rng), 48 * 256 + jitter(rng)};
        const int n = 5 + round * 3;
        std::vector<R::Fixed> poly;
        for (int k = 0; k < n; ++k) {
            const double angle = 2 * 3.14159265358979 * (k + 0.3 * (round % 3)) / n;
            const double radius = (30.0 + 10.0 * std::sin(3.0 * angle) * (round % 2)) * 256;
            R::Fixed p{centre.x + std::llround(radius * std::cos(angle)), centre.y + std::llround(radius * std::sin(angle))};
            if (round % 4 == 1) p = {(p.x / 256) * 256 + 128, (p.y / 256) * 256 + 128};  // on centres
            poly.push_back(p);
        }
        std::vector<int> counts(static_cast<std::size_t>(w) * h, 0);
        for (int k = 0; k < n; ++k) {
            const R::Fixed tri[3] = {centre, poly[k], poly[(k + 1) % n]};
            R::rasterize_add(tri, w, {0, 0, w, h}, counts);
        }
        const R::Mask expected = R::polygon_coverage(poly, w, h);
        int inside = 0;
        for (std::size_t i = 0; i < counts.size(); ++i) {
            ASSERT_EQ(counts[i], int{expected[i]}) << "round " << round << " pixel " << i % w << "," << i / w;
            inside += expected[i];
        }
        EXPECT_GT(inside, 1000);
    }
}

// ---- hand-written cases on the renderer ----------------------------------------------------------

// The top-left rule on the renderer, with expected pixels written out by hand (not via the reference).
TEST(RasterTopLeft, HandComputedCasesOnTheRenderer) {
    const Target target{64, 64, {0, 0, 64, 64}};
    for (int tile : {8, 64}) {
        OneTriangle drawer({.threads = 1, .tile_size = tile}, target);
        auto expect = [&](const R::Fixed (&v)[3], auto&& inside) {
            drawer.draw(v);
            const R::Mask got = drawer.take();
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 64; ++x)
                    EXPECT_EQ(got[static_cast<std::size_t>(y) * 64 + x], inside(x, y) ? 1 : 0)
                        << "tile " << tile << " pixel " << x << "," << y << " of " << describe(v);
        };
        // Legs on centre row 10 and column 10, hypotenuse through the centres with i + j = 40 (a right edge: out).
        const R::Fixed t1[3] = {R::pixel_centre(10, 10), R::pixel_centre(30, 10), R::pixel_centre(10, 30)};
        expect(t1, [](int x, int y) { return x >= 10 && y >= 10 && x + y <= 39; });
        const R::Fixed t1r[3] = {t1[0], t1[2], t1[1]};
        expect(t1r, [](int x, int y) { return x >= 10 && y >= 10 && x + y <= 39; });
        // Its mirror: bottom and right legs are out, the hypotenuse is in.
        const R::Fixed t2[3] = {R::pixel_centre(30, 30), R::pixel_centre(30, 10), R::pixel_centre(10, 30)};
        expect(t2, [](int x, int y) { return x <= 29 && y <= 29 && x + y >= 40; });
        // An 8 x 8 px square with corners on pixel corners, split along its diagonal.
        const R::Fixed s1[3] = {{8 * 256, 8 * 256}, {16 * 256, 8 * 256}, {16 * 256, 16 * 256}};
        const R::Fixed s2[3] = {{8 * 256, 8 * 256}, {16 * 256, 16 * 256}, {8 * 256, 16 * 256}};
        // The diagonal passes through the centres with x == y: a left edge of s1 (interior to its
        // right) and a right edge of s2, so those centres belong to s1.
        expect(s1, [](int x, int y) { return y >= 8 && x < 16 && x >= y; });
        expect(s2, [](int x, int y) { return x >= 8 && y < 16 && x < y; });
        // One unit (1/256 px) beside a centre: just inside / just outside.
        const R::Fixed in[3] = {{20 * 256 + 127, 20 * 256 + 127}, {20 * 256 + 200, 20 * 256 + 127}, {20 * 256 + 127, 20 * 256 + 200}};
        expect(in, [](int x, int y) { return x == 20 && y == 20; });
        const R::Fixed out[3] = {{20 * 256 + 129, 20 * 256 + 120}, {20 * 256 + 200, 20 * 256 + 120}, {20 * 256 + 129, 20 * 256 + 200}};
        expect(out, [](int, int) { return false; });
    }
}

}  // namespace
