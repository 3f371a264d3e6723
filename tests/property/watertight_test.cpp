// Property: meshes are watertight. When triangles tile a region, every pixel of the region is drawn
// exactly once (no cracks, no double hits on shared edges or vertices) and nothing outside it is drawn.
//
// How hits are counted, exactly: one draw call with DepthTest::always, no culling and no discard, and a
// fragment function that increments an atomic counter for its pixel (from in.pos_screen, the pixel
// centre). With depth test `always` the renderer calls fragment() once for every (triangle, covered
// pixel) pair, so the counters are exactly the per-pixel coverage counts, whatever the tile or thread
// that runs them. (The colour buffer is checked too: a pixel is written iff it was counted.)
//
// What "the region" is, exactly: the top-left rule assigns a pixel centre p to a triangle iff the
// point p + (e, e^2) is strictly inside it, for an infinitesimal e > 0. A tiling of a polygon therefore
// covers exactly the pixels whose centre satisfies the same test for the polygon, each once: that set
// is facet_test::raster::polygon_coverage(), computed independently with exact crossing counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <vector>

#include "facet/math/transform.hpp"
#include "facet/renderer.hpp"
#include "support/reference_raster.hpp"

namespace {

using namespace facet;
namespace R = facet_test::raster;

struct Mesh {
    std::vector<Vec4> pos;  // clip space
    std::vector<std::uint32_t> indices;
};

struct Hits {
    std::vector<int> counts;
    DrawStats stats;
};

// Draws the whole mesh in one call and returns per-pixel hit counts (see the file comment).
// Counts every fragment, hidden or not (k_shade_hidden): a pixel covered twice must show.
struct CountingShader {
    static constexpr int k_varyings = 0;
    static constexpr bool k_shade_hidden = true;
    const Mesh* mesh;
    std::vector<std::atomic<int>>* hits;
    int width;
    Vec4 vertex(std::uint32_t i, Varyings<0>&) const { return mesh->pos[i]; }
    Vec4 fragment(const FragmentIn<0>& in) const {
        const int x = static_cast<int>(in.pos_screen.x), y = static_cast<int>(in.pos_screen.y);
        (*hits)[static_cast<std::size_t>(y) * width + x].fetch_add(1, std::memory_order_relaxed);
        return Vec4{1, 1, 1, 1};
    }
};

Hits count_hits(const Mesh& mesh, int width, int height, RendererConfig config) {
    Renderer renderer(config);
    Framebuffer fb(width, height);
    fb.clear(Vec4{0, 0, 0, 0});
    std::vector<std::atomic<int>> hits(static_cast<std::size_t>(width) * height);
    const CountingShader shader{&mesh, &hits, width};
    const DrawState state{.cull = CullMode::none, .depth_test = DepthTest::always, .viewport = {}};
    Hits out;
    out.stats = renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.pos.size()), mesh.indices}, shader);
    out.counts.resize(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        out.counts[i] = hits[i].load();
        EXPECT_EQ(fb.colour_data()[i].r != 0, out.counts[i] > 0) << "colour written iff counted, pixel " << i;
    }
    return out;
}

// Every pixel: expected(x, y) in {0, 1} (or -1 for "0 or 1, not decided by the test") vs the count.
template <class Expected>
::testing::AssertionResult counts_match(const std::vector<int>& counts, int width, int height, Expected expected) {
    int doubles = 0, misses = 0, strays = 0, shown = 0, hit = 0;
    std::ostringstream detail;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int got = counts[static_cast<std::size_t>(y) * width + x];
            const int want = expected(x, y);
            hit += got > 0;
            bool bad = false;
            if (got > 1) ++doubles, bad = true;
            else if (want == 1 && got == 0) ++misses, bad = true;
            else if (want == 0 && got != 0) ++strays, bad = true;
            if (bad && shown < 10) {
                detail << " (" << x << "," << y << "): " << got << " hits, want " << want << ";";
                ++shown;
            }
        }
    if (doubles + misses + strays == 0) return ::testing::AssertionSuccess() << hit << " pixels hit once";
    return ::testing::AssertionFailure() << doubles << " pixels hit more than once, " << misses << " missed, " << strays
                                         << " hit outside the region:" << detail.str();
}

::testing::AssertionResult counts_match(const std::vector<int>& counts, int width, int height, const R::Mask& expected) {
    return counts_match(counts, width, height,
                        [&](int x, int y) { return int{expected[static_cast<std::size_t>(y) * width + x]}; });
}

// Appends triangle (a, b, c) in a random winding starting at a random corner.
void add_triangle(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::mt19937_64& rng) {
    std::uint32_t t[3] = {a, b, c};
    if (rng() & 1) std::swap(t[1], t[2]);
    const int r = static_cast<int>(rng() % 3);
    for (int k = 0; k < 3; ++k) m.indices.push_back(t[(k + r) % 3]);
}

const RendererConfig k_configs[] = {{.threads = 1, .tile_size = 64}, {.threads = 2, .tile_size = 8}, {.threads = 2, .tile_size = 16}};

// ---- (a) a fan of 4096 triangles ------------------------------------------------------------------

struct FanCase {
    const char* name;
    R::Fixed centre;
    double radius_px;
};

void run_fan(const FanCase& fc, std::uint64_t seed) {
    const int W = 256, H = 256;
    const Rect vp{0, 0, W, H};
    const int n = 4096;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    std::vector<R::Fixed> outer(n);
    for (int k = 0; k < n; ++k) {
        const double angle = 2 * 3.14159265358979323846 * (k + jitter(rng)) / n;
        outer[k] = {fc.centre.x + std::llround(fc.radius_px * R::k_sub * std::cos(angle)),
                    fc.centre.y + std::llround(fc.radius_px * R::k_sub * std::sin(angle))};
    }
    Mesh mesh;
    mesh.pos.push_back(R::clip_from_fixed(fc.centre, vp));
    ASSERT_TRUE(R::snaps_exactly(fc.centre, vp));
    for (const R::Fixed& p : outer) {
        ASSERT_TRUE(R::snaps_exactly(p, vp));
        mesh.pos.push_back(R::clip_from_fixed(p, vp));
    }
    for (int k = 0; k < n; ++k) {
        // Precondition: consecutive spokes turn by a small positive angle, so the fan winds once around
        // the centre without overlap and tiles the (star-shaped) outer polygon.
        const R::Fixed a = outer[k], b = outer[(k + 1) % n];
        ASSERT_GT(R::signed_area2(fc.centre, a, b), 0);
        ASSERT_GT((a.x - fc.centre.x) * (b.x - fc.centre.x) + (a.y - fc.centre.y) * (b.y - fc.centre.y), 0);
        add_triangle(mesh, 0, static_cast<std::uint32_t>(k + 1), static_cast<std::uint32_t>((k + 1) % n + 1), rng);
    }
    const R::Mask expected = R::polygon_coverage(outer, W, H);
    for (const RendererConfig& config : k_configs) {
        const Hits hits = count_hits(mesh, W, H, config);
        EXPECT_TRUE(counts_match(hits.counts, W, H, expected))
            << fc.name << ", tile " << config.tile_size << ", threads " << config.threads;
        EXPECT_EQ(hits.stats.triangles_in, static_cast<std::uint64_t>(n));
        EXPECT_EQ(hits.stats.triangles_clipped, 0u);
    }
}

TEST(Watertight, FanOf4096AroundASubPixelCentre) {
    run_fan({"sub-pixel centre", {128 * 256 + 77, 127 * 256 + 173}, 110.0}, 1);
}
TEST(Watertight, FanOf4096AroundAPixelCentre) { run_fan({"centre on a pixel centre", R::pixel_centre(127, 128), 100.0}, 2); }
TEST(Watertight, FanOf4096AroundAPixelCorner) { run_fan({"centre on a pixel corner", {100 * 256, 140 * 256}, 90.0}, 3); }
// Outer polygon far beyond the viewport (still inside the guard band): every pixel exactly once.
TEST(Watertight, FanOf4096CoveringTheWholeViewport) {
    run_fan({"covering", {128 * 256 + 3, 128 * 256 - 5}, 7000.0}, 4);
}

// ---- (b), (c) a jittered grid of 80,000 triangles -------------------------------------------------

struct Grid {
    int cells_x, cells_y;
    std::vector<R::Fixed> points;  // (cells_x + 1) * (cells_y + 1), row-major
    R::Fixed at(int i, int j) const { return points[static_cast<std::size_t>(j) * (cells_x + 1) + i]; }
};

// A grid over [x0, x1] x [y0, y1] (fixed point). Boundary points move only along the boundary, so the
// region stays exactly the rectangle; interior points are jittered by up to 0.2 of a cell, or put on
// the nearest pixel centre or pixel corner (at most half a pixel away), so no triangle folds over.
Grid jittered_grid(int cells_x, int cells_y, R::Fixed lo, R::Fixed hi, std::mt19937_64& rng) {
    Grid g{cells_x, cells_y, {}};
    const double cw = static_cast<double>(hi.x - lo.x) / cells_x, ch = static_cast<double>(hi.y - lo.y) / cells_y;
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    std::uniform_int_distribution<int> pick(0, 9);
    auto round_to = [](double v, std::int64_t offset) {  // nearest value of 256 k + offset
        return static_cast<std::int64_t>(std::floor((v - offset) / R::k_sub + 0.5)) * R::k_sub + offset;
    };
    for (int j = 0; j <= cells_y; ++j)
        for (int i = 0; i <= cells_x; ++i) {
            double x = lo.x + i * cw, y = lo.y + j * ch;
            const bool edge_x = i == 0 || i == cells_x, edge_y = j == 0 || j == cells_y;
            R::Fixed p;
            const int choice = pick(rng);
            if (!edge_x) x += u(rng) * cw;
            if (!edge_y) y += u(rng) * ch;
            p = {std::llround(x), std::llround(y)};
            if (!edge_x && !edge_y && choice == 0) p = {round_to(lo.x + i * cw, 128), round_to(lo.y + j * ch, 128)};
            if (!edge_x && !edge_y && choice == 1) p = {round_to(lo.x + i * cw, 0), round_to(lo.y + j * ch, 0)};
            if (edge_x) p.x = i == 0 ? lo.x : hi.x;
            if (edge_y) p.y = j == 0 ? lo.y : hi.y;
            g.points.push_back(p);
        }
    return g;
}

// Two triangles per cell, split along a random diagonal, random winding. `clip_of` gives each grid
// point's clip position (shared by every triangle that uses it).
template <class ClipOf>
Mesh grid_mesh(const Grid& g, std::mt19937_64& rng, ClipOf clip_of) {
    Mesh m;
    for (const R::Fixed& p : g.points) m.pos.push_back(clip_of(p));
    const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (g.cells_x + 1) + i); };
    for (int j = 0; j < g.cells_y; ++j)
        for (int i = 0; i < g.cells_x; ++i) {
            const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            if (rng() & 1) {
                add_triangle(m, a, b, c, rng);
                add_triangle(m, a, c, d, rng);
            } else {
                add_triangle(m, a, b, d, rng);
                add_triangle(m, b, c, d, rng);
            }
        }
    return m;
}

// Precondition: every triangle of the grid, in its generated winding before the random flips, has the
// same orientation as the grid (no fold-over), checked on the intended fixed-point positions.
::testing::AssertionResult no_fold_over(const Grid& g) {
    for (int j = 0; j < g.cells_y; ++j)
        for (int i = 0; i < g.cells_x; ++i) {
            const R::Fixed a = g.at(i, j), b = g.at(i + 1, j), c = g.at(i + 1, j + 1), d = g.at(i, j + 1);
            for (const auto& t : {std::array{a, b, c}, std::array{a, c, d}, std::array{a, b, d}, std::array{b, c, d}})
                if (R::signed_area2(t[0], t[1], t[2]) <= 0)
                    return ::testing::AssertionFailure() << "cell " << i << "," << j << " folds over";
        }
    return ::testing::AssertionSuccess();
}

constexpr int k_grid_w = 512, k_grid_h = 512;
// Region boundaries on pixel centres: x in [20.5, 490.5], y in [13.5, 500.5]. By the top-left rule the
// left and top boundary centres are in, the right and bottom ones out: pixels [20, 490) x [13, 500).
const R::Fixed k_grid_lo = R::pixel_centre(20, 13), k_grid_hi = R::pixel_centre(490, 500);
int in_grid_region(int x, int y) { return x >= 20 && x < 490 && y >= 13 && y < 500; }

TEST(Watertight, GridRegionExpectationIsThePolygonRule) {  // the hand-written region == polygon_coverage
    const std::vector<R::Fixed> rect = {k_grid_lo, {k_grid_hi.x, k_grid_lo.y}, k_grid_hi, {k_grid_lo.x, k_grid_hi.y}};
    const R::Mask m = R::polygon_coverage(rect, k_grid_w, k_grid_h);
    for (int y = 0; y < k_grid_h; ++y)
        for (int x = 0; x < k_grid_w; ++x)
            ASSERT_EQ(int{m[static_cast<std::size_t>(y) * k_grid_w + x]}, in_grid_region(x, y)) << x << "," << y;
}

TEST(Watertight, JitteredGridOf80000Triangles) {
    std::mt19937_64 rng(20);
    const Grid g = jittered_grid(200, 200, k_grid_lo, k_grid_hi, rng);
    ASSERT_TRUE(no_fold_over(g));
    const Rect vp{0, 0, k_grid_w, k_grid_h};
    const Mesh mesh = grid_mesh(g, rng, [&](R::Fixed p) { return R::clip_from_fixed(p, vp); });
    for (const R::Fixed& p : g.points) ASSERT_TRUE(R::snaps_exactly(p, vp));
    ASSERT_EQ(mesh.indices.size(), 3u * 80000);
    for (const RendererConfig& config : k_configs) {
        const Hits hits = count_hits(mesh, k_grid_w, k_grid_h, config);
        EXPECT_TRUE(counts_match(hits.counts, k_grid_w, k_grid_h, in_grid_region))
            << "tile " << config.tile_size << ", threads " << config.threads;
        EXPECT_EQ(hits.stats.triangles_in, 80000u);
        EXPECT_EQ(hits.stats.triangles_culled, 0u);
    }
}

// The same grid with a random w per vertex: clip = (ndc * w, ndc_y * w, z * w, w), so every vertex
// goes through a real perspective divide. Shared vertices share their clip coordinates, so they snap
// to the same point in every triangle. Interior vertices have w anywhere in [0.5, 4] (their snapped
// position may move by a rounding unit, which the 0.2-cell margin absorbs); boundary vertices get a
// power-of-two w so that they still snap exactly onto the region's boundary.
TEST(Watertight, JitteredGridWithRandomW) {
    std::mt19937_64 rng(21);
    const Grid g = jittered_grid(200, 200, k_grid_lo, k_grid_hi, rng);
    ASSERT_TRUE(no_fold_over(g));
    const Rect vp{0, 0, k_grid_w, k_grid_h};
    std::uniform_real_distribution<float> any_w(0.5f, 4.0f), any_z(0.05f, 0.95f);
    const float powers[] = {0.5f, 1.0f, 2.0f, 4.0f};
    int inexact = 0;
    const Mesh mesh = grid_mesh(g, rng, [&](R::Fixed p) {
        const bool boundary = p.x == k_grid_lo.x || p.x == k_grid_hi.x || p.y == k_grid_lo.y || p.y == k_grid_hi.y;
        const float w = boundary ? powers[rng() % 4] : any_w(rng);
        const float z = any_z(rng);
        if (boundary) {
            EXPECT_TRUE(R::snaps_exactly(p, vp, z, w));
        }
        inexact += !R::snaps_exactly(p, vp, z, w);
        return R::clip_from_fixed(p, vp, z, w);
    });
    EXPECT_GT(inexact, 10000) << "most interior vertices should need a real (rounded) division";
    for (const RendererConfig& config : k_configs) {
        const Hits hits = count_hits(mesh, k_grid_w, k_grid_h, config);
        EXPECT_TRUE(counts_match(hits.counts, k_grid_w, k_grid_h, in_grid_region))
            << "tile " << config.tile_size << ", threads " << config.threads;
        EXPECT_EQ(hits.stats.triangles_clipped, 0u);
    }
}

// The counting method can fail: a triangle drawn twice is a double hit, a missing one is a crack.
TEST(Watertight, CountingDetectsDoubleHitsAndCracks) {
    std::mt19937_64 rng(24);
    const Grid g = jittered_grid(20, 20, k_grid_lo, k_grid_hi, rng);
    const Rect vp{0, 0, k_grid_w, k_grid_h};
    Mesh mesh = grid_mesh(g, rng, [&](R::Fixed p) { return R::clip_from_fixed(p, vp); });
    const RendererConfig config{.threads = 2, .tile_size = 16};
    EXPECT_TRUE(counts_match(count_hits(mesh, k_grid_w, k_grid_h, config).counts, k_grid_w, k_grid_h, in_grid_region));
    Mesh doubled = mesh;
    doubled.indices.insert(doubled.indices.end(), mesh.indices.begin() + 300, mesh.indices.begin() + 303);
    EXPECT_FALSE(counts_match(count_hits(doubled, k_grid_w, k_grid_h, config).counts, k_grid_w, k_grid_h, in_grid_region));
    Mesh cracked = mesh;
    cracked.indices.erase(cracked.indices.begin() + 300, cracked.indices.begin() + 303);
    EXPECT_FALSE(counts_match(count_hits(cracked, k_grid_w, k_grid_h, config).counts, k_grid_w, k_grid_h, in_grid_region));
}

// ---- through the clipper --------------------------------------------------------------------------

// A coarse grid spanning +-20000 px around a 256 x 256 viewport, far past the 8192 px guard band, with
// random w: most triangles are cut by the guard-band planes and their polygons fanned into new
// triangles. Every pixel of the viewport is still drawn exactly once.
TEST(Watertight, GridCrossingTheGuardBand) {
    const int W = 256, H = 256;
    std::mt19937_64 rng(22);
    std::uniform_real_distribution<float> any_w(0.5f, 4.0f);
    for (int round = 0; round < 4; ++round) {
        const std::int64_t reach = std::int64_t{20000} * R::k_sub;
        const R::Fixed lo{128 * 256 - reach + round * 77, 128 * 256 - reach - round * 33};
        const R::Fixed hi{128 * 256 + reach - round * 51, 128 * 256 + reach + round * 91};
        const Grid g = jittered_grid(6 + round, 5 + round, lo, hi, rng);
        ASSERT_TRUE(no_fold_over(g));
        const Mesh mesh = grid_mesh(g, rng, [&](R::Fixed p) { return R::clip_from_fixed(p, {0, 0, W, H}, 0.5f, any_w(rng)); });
        for (const RendererConfig& config : k_configs) {
            const Hits hits = count_hits(mesh, W, H, config);
            EXPECT_TRUE(counts_match(hits.counts, W, H, [](int, int) { return 1; }))
                << "round " << round << ", tile " << config.tile_size << ", threads " << config.threads;
            EXPECT_GT(hits.stats.triangles_clipped, 0u);
        }
    }
}

// A ground plane made of a 64 x 64 grid, from behind the eye to far ahead, seen by a perspective
// camera: triangles cross the near plane (grid points level with the eye have w exactly 0) and the
// guard band. The eye is 1 unit above the plane looking horizontally, so the horizon is the row
// boundary y = 128 of the 256-pixel target; the far edge of the plane (500 units away) projects to
// y = 128 + 128 / 500 * f (f = 1 / tan(45 deg) = 1), above the centre of row 128. So rows 128.. are
// the plane, drawn exactly once, and rows ..127 are sky, never drawn.
TEST(Watertight, GroundPlaneGridThroughTheNearPlane) {
    const int W = 256, H = 256, n = 64;
    const Mat4 clip_from_world =
        perspective_rh_zo(radians(90.0f), 1.0f, 0.1f, 1000.0f) * look_at_rh({0, 1, 0}, {0, 1, -1}, {0, 1, 0});
    std::mt19937_64 rng(23);
    Mesh mesh;
    int zero_w = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -500.0f + 1000.0f * i / n, z = -500.0f + 1000.0f * j / n;
            mesh.pos.push_back(clip_from_world * Vec4{x, 0, z, 1});
            zero_w += mesh.pos.back().w == 0.0f;
        }
    EXPECT_EQ(zero_w, n + 1) << "the grid row at z = 0 is level with the eye: w = 0";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto id = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
            add_triangle(mesh, id(i, j), id(i + 1, j), id(i + 1, j + 1), rng);
            add_triangle(mesh, id(i, j), id(i + 1, j + 1), id(i, j + 1), rng);
        }
    for (const RendererConfig& config : k_configs) {
        const Hits hits = count_hits(mesh, W, H, config);
        EXPECT_TRUE(counts_match(hits.counts, W, H, [](int, int y) { return y >= 128 ? 1 : 0; }))
            << "tile " << config.tile_size << ", threads " << config.threads;
        EXPECT_GT(hits.stats.triangles_clipped, 0u);
        EXPECT_EQ(hits.stats.triangles_invalid, 0u);
    }
}

}  // namespace
