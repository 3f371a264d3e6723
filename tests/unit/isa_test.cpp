// The SIMD kernels against their scalar specification, on every ISA this CPU runs: coverage of
// random triangles of every size (from sub-pixel to the edge of the guard band, where the 32-bit
// form of the edge functions is tightest) must be the reference's bit for bit, so must the fused
// coverage-and-depth pass (depth buffer, owners, covered pixels) on tiles of every width, so must the
// compiled vertex stages of the built-in shaders against their vertex(), and the ISA switch itself
// must do what it says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "facet/detail/front_end.hpp"
#include "facet/isa.hpp"
#include "facet/shaders.hpp"
#include "geometry/project.hpp"
#include "raster/segment.hpp"
#include "setup/setup.hpp"
#include "support/pixels.hpp"
#include "tile/depth_pass.hpp"
#include "tile/tile_store.hpp"

namespace {

using namespace facet;
using namespace facet::detail;

// Restores the default ISA when a test ends, whatever it selected.
using facet_test::IsaGuard;

FrontEndParams params_for(int width, int height) {
    FrontEndParams p{};
    p.state.cull = CullMode::none;
    p.scissor = {0, 0, width, height};
    p.vp_x = 0, p.vp_y = 0, p.vp_w = static_cast<float>(width), p.vp_h = static_cast<float>(height);
    p.tile_size = 64;
    p.tiles_x = (width + 63) / 64, p.tiles_y = (height + 63) / 64;
    return p;
}

// A random triangle whose vertices lie within `extent` pixels of `centre` (fixed point).
void random_triangle(std::mt19937& rng, double centre_x, double centre_y, double extent, ScreenVertex (&v)[3]) {
    std::uniform_real_distribution<double> offset(-extent, extent);
    for (ScreenVertex& s : v) {
        const double x = std::clamp(centre_x + offset(rng), -16384.0, 16384.0);
        const double y = std::clamp(centre_y + offset(rng), -16384.0, 16384.0);
        s = {static_cast<std::int32_t>(std::lround(x * k_subpixel_one)),
             static_cast<std::int32_t>(std::lround(y * k_subpixel_one)), 0.5f, 1.0f};
    }
}

bool same_coverage(const TileCoverage& a, bool any_a, const TileCoverage& b, bool any_b) {
    if (any_a != any_b) return false;
    if (!any_a) return true;
    if (a.first_row != b.first_row || a.last_row != b.last_row) return false;
    for (int r = a.first_row; r <= a.last_row; ++r)
        if (a.rows[r] != b.rows[r]) return false;
    return true;
}

TEST(Isa, TheSwitchListsSelectsAndRestores) {
    IsaGuard guard;
    const std::vector<std::string> isas = available_isas();
    ASSERT_FALSE(isas.empty());
    EXPECT_EQ(isas.back(), "scalar");
    EXPECT_EQ(active_isa(), isas.front());
    for (const std::string& name : isas) {
        ASSERT_TRUE(select_isa(name)) << name;
        EXPECT_EQ(active_isa(), name);
    }
    EXPECT_FALSE(select_isa("altivec"));
    EXPECT_EQ(active_isa(), "scalar");  // a refused name changes nothing
    EXPECT_TRUE(select_isa("best"));
    EXPECT_EQ(active_isa(), isas.front());
}

TEST(Isa, CoverageOfRandomTrianglesEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    const int width = 8192, height = 8192;
    const FrontEndParams params = params_for(width, height);
    std::mt19937 rng(20261121);
    const double extents[] = {0.7, 3, 12, 40, 200, 3000, 16384};
    const int tile_sizes[] = {8, 16, 32, 64};
    const std::uint32_t refs[3] = {0, 1, 2};

    int compared = 0, covered = 0;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        std::mt19937 local(rng());
        for (int i = 0; i < 6000; ++i) {
            const double extent = extents[i % std::size(extents)];
            std::uniform_real_distribution<double> where(-64, width + 64);
            ScreenVertex v[3];
            random_triangle(local, where(local), where(local), extent, v);
            TriangleSetup t{};
            if (setup_triangle(v, refs, params, t) != SetupResult::ok) continue;
            // A few tiles of a random size that overlap the triangle's bounds.
            const int tile = tile_sizes[local() % std::size(tile_sizes)];
            for (int k = 0; k < 4; ++k) {
                std::uniform_int_distribution<int> tx(t.min_x / tile, t.max_x / tile), ty(t.min_y / tile, t.max_y / tile);
                const int x0 = tx(local) * tile, y0 = ty(local) * tile;
                const PixelRect rect{x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height)};
                TileCoverage simd{}, reference{};
                const bool any_simd = rasterize_tile(t, rect, simd);
                const bool any_reference = rasterize_tile_reference(t, rect, reference);
                ASSERT_TRUE(same_coverage(simd, any_simd, reference, any_reference))
                    << isa << ": triangle " << i << " (" << v[0].x << "," << v[0].y << ") (" << v[1].x << ","
                    << v[1].y << ") (" << v[2].x << "," << v[2].y << "), tile at " << x0 << "," << y0 << " size " << tile;
                ++compared;
                covered += any_reference;
            }
        }
    }
    // The comparison saw many tiles with coverage and many without.
    EXPECT_GT(covered, 5000);
    EXPECT_GT(compared - covered, 1000);
}

// How random_tile draws a tile: full-size (64) sides one time in four, or three in four; its
// left edge anywhere, or against the target's right edge one time in four (its bottom edge is
// against the target's one time in four either way).
struct TileOdds {
    bool mostly_full;
    bool right_edge_often;
};

// A tile of sides 1..64 inside a width x height target.
PixelRect random_tile(std::mt19937& rng, int width, int height, TileOdds odds) {
    std::uniform_int_distribution<int> size(1, 64), coin(0, 3);
    const auto side = [&] { return (coin(rng) != 0) == odds.mostly_full ? 64 : size(rng); };
    const int w = side(), h = side();
    const int x0 = !odds.right_edge_often || coin(rng) ? std::uniform_int_distribution<int>(0, width - w)(rng) : width - w;
    const int y0 = coin(rng) ? std::uniform_int_distribution<int>(0, height - h)(rng) : height - h;
    return {x0, y0, x0 + w, y0 + h};
}

// One tile's pass one run by resolve_triangle (whichever ISA is selected) or by the reference.
struct DepthPassState {
    std::vector<float> depth;
    TileBuffers buffers;
    std::vector<bool> any;  // each triangle's return value
};

bool same_state(const DepthPassState& a, const DepthPassState& b, PixelRect tile) {
    if (a.depth.size() != b.depth.size() || a.any != b.any) return false;
    if (std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) != 0) return false;
    for (int r = 0; r < tile.y1 - tile.y0; ++r) {
        if (a.buffers.covered[r] != b.buffers.covered[r]) return false;
        for (int i = 0; i < tile.x1 - tile.x0; ++i)
            if (a.buffers.owner[r * k_max_tile_size + i] != b.buffers.owner[r * k_max_tile_size + i]) return false;
    }
    return true;
}

// A random tile of a width x height target for a bin, its depth test and write flag, and where the
// bin's records are centred: within 4 pixels of the tile.
struct BinTile {
    PixelRect tile;
    DepthTest test;
    bool write;
    std::uniform_real_distribution<double> near_x, near_y;
};
BinTile random_bin_tile(std::mt19937& rng, int width, int height) {
    constexpr DepthTest tests[] = {DepthTest::less, DepthTest::lequal, DepthTest::greater, DepthTest::always};
    const PixelRect tile = random_tile(rng, width, height, {.mostly_full = true, .right_edge_often = false});
    const DepthTest test = tests[rng() % std::size(tests)];
    const bool write = std::uniform_int_distribution<int>(0, 3)(rng) != 0;
    return {tile, test, write, std::uniform_real_distribution<double>(tile.x0 - 4.0, tile.x1 + 4.0),
            std::uniform_real_distribution<double>(tile.y0 - 4.0, tile.y1 + 4.0)};
}

// `bin` over `tile` of a width x height target (depth 1 everywhere) by isa's kernel and by the scalar
// specification, in two calls as for two chunks' bins (the second's ids follow the first's): the
// same records listed, in the same order, and the same depths, owners and covered pixels. Adds the
// number listed to `listed`.
void expect_bin_as_specified(const std::string& isa, const std::vector<TriangleSetup>& bin, std::size_t split,
                             PixelRect tile, int width, int height, DepthTest test, bool write, DepthPassState& simd,
                             DepthPassState& spec, int& listed, bool large = false) {
    ASSERT_LE(split, bin.size());
    std::vector<std::size_t> order[2];
    for (DepthPassState* s : {&simd, &spec}) {
        ASSERT_TRUE(select_isa(s == &simd ? isa : "scalar"));
        s->depth.assign(static_cast<std::size_t>(width) * height, 1.0f);
        s->buffers.begin(tile, 1, {nullptr, s->depth.data(), width});
        const ResolveBinKernel kernel = resolve_bin_kernel(test, write, large);
        kernel(bin.data(), split, tile, s->buffers);
        kernel(bin.data() + split, bin.size() - split, tile, s->buffers);
        s->buffers.end(tile, {nullptr, s->depth.data(), width}, write);
        for (const TriangleSetup* t : s->buffers.triangles)
            order[s == &spec].push_back(static_cast<std::size_t>(t - bin.data()));
    }
    ASSERT_EQ(order[0], order[1]) << isa;
    ASSERT_TRUE(same_state(simd, spec, tile))
        << isa << ": tile at " << tile.x0 << "," << tile.y0 << " size " << tile.x1 - tile.x0 << "x" << tile.y1 - tile.y0;
    listed += static_cast<int>(order[1].size());
}

TEST(Isa, FusedDepthPassEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    const int width = 150, height = 140;
    const FrontEndParams params = params_for(width, height);
    const double extents[] = {0.7, 2, 5, 12, 40, 200, 3000};
    const DepthTest tests[] = {DepthTest::less, DepthTest::lequal, DepthTest::equal, DepthTest::greater,
                               DepthTest::always};
    const std::uint32_t refs[3] = {0, 1, 2};
    auto reference = [](const DepthJob& job) {
        bool any = false;
        auto with_write = [&]<DepthTest D>() {
            any = job.write ? resolve_triangle_reference<D, true>(job) : resolve_triangle_reference<D, false>(job);
        };
        with_depth_test(job.test, with_write);
        return any;
    };
    auto simd = std::make_unique<DepthPassState>(), spec = std::make_unique<DepthPassState>();
    int tiles = 0, passes = 0;
    for (const std::string& isa : available_isas()) {
        std::mt19937 rng(20261122);
        for (int n = 0; n < 800; ++n) {
            // A tile of any width and height up to 64 anywhere in the target, touching its edges often.
            const PixelRect tile = random_tile(rng, width, height, {.mostly_full = false, .right_edge_often = true});
            const int x0 = tile.x0, y0 = tile.y0, w = tile.x1 - tile.x0, h = tile.y1 - tile.y0;
            std::uniform_int_distribution<int> coin(0, 3);
            const DepthTest test = tests[rng() % std::size(tests)];
            const bool write = coin(rng) != 0;
            std::vector<float> depth(static_cast<std::size_t>(width) * height);
            std::uniform_real_distribution<float> unit(0, 1);
            for (float& d : depth) d = coin(rng) ? 1.0f : unit(rng);
            for (DepthPassState* s : {simd.get(), spec.get()}) {
                s->depth = depth;
                s->buffers.begin(tile, 1, {nullptr, s->depth.data(), width});
                s->any.clear();
            }
            // Triangles near the tile, some drawn twice so equal depths meet.
            TriangleSetup t{};
            for (int k = 0; k < 12; ++k) {
                if (k == 0 || coin(rng)) {
                    const double extent = extents[rng() % std::size(extents)];
                    std::uniform_real_distribution<double> near_x(x0 - 8.0, x0 + w + 8.0), near_y(y0 - 8.0, y0 + h + 8.0);
                    ScreenVertex v[3];
                    random_triangle(rng, near_x(rng), near_y(rng), extent, v);
                    for (ScreenVertex& s : v) s.z = unit(rng) * 1.2f - 0.1f;
                    if (setup_triangle(v, refs, params, t) != SetupResult::ok) continue;
                }
                const auto id = static_cast<std::uint32_t>(k);
                ASSERT_TRUE(select_isa(isa));
                simd->any.push_back(resolve_triangle({&t, tile, &simd->buffers, id, test, write}));
                spec->any.push_back(reference({&t, tile, &spec->buffers, id, test, write}));
                passes += spec->any.back();
            }
            for (DepthPassState* s : {simd.get(), spec.get()}) s->buffers.end(tile, {nullptr, s->depth.data(), width}, write);
            ASSERT_TRUE(same_state(*simd, *spec, tile))
                << isa << ": tile " << n << " at " << x0 << "," << y0 << " size " << w << "x" << h;
            ++tiles;
        }
    }
    EXPECT_GT(passes, 1000);
    EXPECT_EQ(tiles, 800 * static_cast<int>(available_isas().size()));
}

// A whole bin at once: the kernel lists the triangles that pass somewhere, in order, each owning its
// pixels under its index in the list, exactly as resolve_triangle_reference one triangle at a time.
// Many small triangles over one tile (the kernel's rows in groups, the tile's last rows, tiles
// narrower than a vector) and some large ones that reach far past it; depths past [0, 1] and -0.
TEST(Isa, BinDepthPassEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    const int width = 200, height = 130;
    const FrontEndParams params = params_for(width, height);
    const double extents[] = {0.6, 1.5, 3, 6, 20, 5000};
    const std::uint32_t refs[3] = {0, 1, 2};
    auto simd = std::make_unique<DepthPassState>(), spec = std::make_unique<DepthPassState>();
    int tiles = 0, listed = 0, large_listed = 0;
    for (const std::string& isa : available_isas()) {
        std::mt19937 rng(20261121);
        for (int n = 0; n < 300; ++n) {
            BinTile c = random_bin_tile(rng, width, height);
            std::uniform_int_distribution<int> coin(0, 3);
            std::vector<TriangleSetup> bin;
            std::uniform_real_distribution<float> unit(0, 1);
            while (bin.size() < 150) {
                const double extent = extents[rng() % std::size(extents)];
                ScreenVertex v[3];
                random_triangle(rng, c.near_x(rng), c.near_y(rng), extent, v);
                // Mostly inside [0, 1]; some reaching past it (the clamp), some at -0 (which the
                // clamp keeps, as depth_at does: depths are compared byte for byte).
                const int depths = coin(rng) ? 0 : 1 + coin(rng) % 2;
                for (ScreenVertex& s : v) s.z = depths == 0 ? unit(rng) : depths == 1 ? unit(rng) * 1.2f - 0.1f : -0.0f;
                TriangleSetup t{};
                if (setup_triangle(v, refs, params, t) == SetupResult::ok) bin.push_back(t);
                if (coin(rng) == 0) bin.push_back(bin.empty() ? t : bin.back());  // equal depths meet
            }
            ASSERT_NO_FATAL_FAILURE(expect_bin_as_specified(isa, bin, 100, c.tile, width, height, c.test, c.write, *simd, *spec, listed))
                << "tile " << n;
            // The kernel for draws of large triangles (its own rows for large rectangles).
            ASSERT_NO_FATAL_FAILURE(
                expect_bin_as_specified(isa, bin, 100, c.tile, width, height, c.test, c.write, *simd, *spec, large_listed, true))
                << "tile " << n << ", large";
            ++tiles;
        }
    }
    EXPECT_GT(listed, 5000);
    EXPECT_EQ(large_listed, listed);
    EXPECT_EQ(tiles, 300 * static_cast<int>(available_isas().size()));
}

// The same for bins of line segments' records (raster/segment.hpp): thin and wide, short and
// crossing the tile, and long ones whose edges do not fit 32 bits over their bounds (small_edges
// false); the kernel reads a small segment's four edges from the record in one step per strip. Some
// triangles among them (a line draw's quads left as two triangles), which end the kernel's run of
// segments (resolve_segment_run) and start another.
TEST(Isa, SegmentBinDepthPassEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    const int width = 200, height = 130;
    const PixelRect scissor{0, 0, width, height};
    const double lengths[] = {0.7, 2, 5, 12, 40, 600, 5000};
    const double half_widths[] = {0.5, 0.5, 0.5, 1, 2.5, 6};
    const FrontEndParams params = params_for(width, height);
    const std::uint32_t refs[3] = {0, 1, 2};
    auto simd = std::make_unique<DepthPassState>(), spec = std::make_unique<DepthPassState>();
    int tiles = 0, listed = 0, small = 0, large = 0, triangles = 0;
    for (const std::string& isa : available_isas()) {
        std::mt19937 rng(20261127);
        for (int n = 0; n < 60; ++n) {
            BinTile c = random_bin_tile(rng, width, height);
            std::uniform_int_distribution<int> coin(0, 3);
            std::vector<TriangleSetup> bin;
            std::uniform_real_distribution<float> unit(0, 1);
            std::uniform_real_distribution<double> angle(0, 6.283185307179586);
            while (bin.size() < 100) {
                const double length = lengths[rng() % std::size(lengths)], turn = angle(rng);
                const double cx = c.near_x(rng), cy = c.near_y(rng);
                const double ends[2][2] = {{cx - 0.5 * length * std::cos(turn), cy - 0.5 * length * std::sin(turn)},
                                           {cx + 0.5 * length * std::cos(turn), cy + 0.5 * length * std::sin(turn)}};
                ScreenVertex v[2];
                for (int i = 0; i < 2; ++i)
                    v[i] = {static_cast<std::int32_t>(std::lround(ends[i][0] * k_subpixel_one)),
                            static_cast<std::int32_t>(std::lround(ends[i][1] * k_subpixel_one)),
                            coin(rng) ? unit(rng) : unit(rng) * 1.2f - 0.1f, 1.0f};
                if (v[0].x == v[1].x && v[0].y == v[1].y) continue;
                const SegmentEnd end = square_end(v[0], v[1], half_widths[rng() % std::size(half_widths)]);
                TriangleSetup t{};
                if (segment_record(v[0], v[1], end, end, 0, 1, scissor, t) != SegmentResult::record) continue;
                (t.small_edges ? small : large) += isa == available_isas().front();
                bin.push_back(t);
                if (coin(rng) == 0) bin.push_back(t);  // equal depths meet
                if (rng() % 8 == 0) {  // a quad left as two triangles: the kernel's run of segments ends
                    ScreenVertex tv[3];
                    random_triangle(rng, c.near_x(rng), c.near_y(rng), 3, tv);
                    for (ScreenVertex& s : tv) s.z = unit(rng);
                    TriangleSetup tri{};
                    if (setup_triangle(tv, refs, params, tri) != SetupResult::ok) continue;
                    bin.push_back(tri);
                    triangles += isa == available_isas().front();
                }
            }
            ASSERT_NO_FATAL_FAILURE(expect_bin_as_specified(isa, bin, 60, c.tile, width, height, c.test, c.write, *simd, *spec, listed))
                << "tile " << n;
            ++tiles;
        }
    }
    EXPECT_GT(listed, 1000);
    EXPECT_GT(small, 1000);
    EXPECT_GT(large, 100);
    EXPECT_GT(triangles, 200);
    EXPECT_EQ(tiles, 60 * static_cast<int>(available_isas().size()));
}

// The projection pass on every ISA against project_vertex one vertex at a time: outcodes and snapped
// screen positions byte for byte, on clip-space positions inside, on and outside every plane, behind
// the eye, at the guard band, huge, infinite and NaN, in blocks whose length is not a whole number of
// vectors.
TEST(Isa, ProjectionEqualsTheScalarSpecificationOnEveryIsa) {
    IsaGuard guard;
    FrontEndParams params = params_for(1920, 1080);
    params.vp_x = 13, params.vp_y = 7, params.vp_w = 1700, params.vp_h = 1000;
    const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-7f, 1e-6f, 1e30f, -1e30f, 9.64f, -9.64f,
                              std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::quiet_NaN()};
    std::mt19937 rng(20261121);
    std::uniform_real_distribution<float> unit(-1.2f, 1.2f), far(-30.0f, 30.0f);
    std::uniform_int_distribution<int> kind(0, 9);
    ClipVertices base;
    const std::size_t n = 5003;
    base.resize(n, 1);
    for (Vec4& p : base.pos) {
        const float w = kind(rng) == 0 ? specials[rng() % std::size(specials)] : std::abs(far(rng)) + 0.01f;
        auto coordinate = [&] {
            const int k = kind(rng);
            if (k == 0) return specials[rng() % std::size(specials)];
            if (k == 1) return far(rng) * w;
            return unit(rng) * w;
        };
        p = {coordinate(), coordinate(), (unit(rng) + 1.2f) / 2.4f * w * (kind(rng) == 0 ? 1.5f : 1.0f), w};
    }
    int inside = 0, invalid = 0;
    for (const std::string& isa : available_isas()) {
        ClipVertices simd = base, spec = base;
        ASSERT_TRUE(select_isa(isa));
        for (std::size_t first = 0; first < n; first += 1001) project_vertices(simd, first, std::min(n, first + 1001), params);
        ASSERT_TRUE(select_isa("scalar"));
        for (std::size_t first = 0; first < n; first += 1001) project_vertices(spec, first, std::min(n, first + 1001), params);
        for (std::size_t i = 0; i < n; ++i) {
            ASSERT_EQ(simd.outcode[i], spec.outcode[i]) << isa << ": vertex " << i;
            ASSERT_EQ(std::memcmp(&simd.screen[i], &spec.screen[i], sizeof(ScreenVertex)), 0) << isa << ": vertex " << i;
            inside += isa == "scalar" && spec.outcode[i] == 0;
            invalid += isa == "scalar" && spec.outcode[i] == k_outcode_invalid;
        }
    }
    // The positions reached every kind of result.
    EXPECT_GT(inside, 1000);
    EXPECT_GT(invalid, 100);
}

// A finished tile written to the target: every ISA writes what store_tile_row_reference specifies,
// values where covered and the fill elsewhere, on aligned targets (streamed) and unaligned ones,
// for tiles of every width, and touches nothing outside the tile.
TEST(Isa, TileStoreWithCoverageEqualsTheSpecificationOnEveryIsa) {
    IsaGuard guard;
    std::mt19937 rng(20261121);
    alignas(64) std::uint32_t rows[k_max_tile_size * k_max_tile_size];
    std::uint64_t covered[k_max_tile_size];
    const int stride = 256;
    std::vector<std::uint32_t, CacheLineAllocator<std::uint32_t>> got(static_cast<std::size_t>(stride) * 80),
        want(got.size());
    int streamed_tiles = 0;
    for (const std::string& isa : available_isas()) {
        for (int n = 0; n < 200; ++n) {
            for (std::uint32_t& v : rows) v = static_cast<std::uint32_t>(rng());
            for (std::uint64_t& c : covered) c = (std::uint64_t{rng()} << 32) | rng();
            if (n % 3 == 0) covered[n % 64] = 0;
            const int width = n % 4 == 0 ? 1 + static_cast<int>(rng() % 64) : 64 - 16 * static_cast<int>(rng() % 4);
            const int height = 1 + static_cast<int>(rng() % 64);
            const int x0 = n % 2 == 0 ? 16 * static_cast<int>(rng() % 8) : static_cast<int>(rng() % 128);
            const PixelRect tile{x0, 3, x0 + width, 3 + height};
            const std::uint32_t fill = static_cast<std::uint32_t>(rng());
            std::fill(got.begin(), got.end(), 0xdeadbeefu);
            std::fill(want.begin(), want.end(), 0xdeadbeefu);
            ASSERT_TRUE(select_isa(isa));
            store_tile_rows(rows, k_max_tile_size, got.data() + 3 * stride + x0, tile, stride, true, covered, fill);
            for (int r = 0; r < height; ++r)
                store_tile_row_reference(rows + r * k_max_tile_size, covered + r, fill,
                                         want.data() + (3 + r) * stride + x0, width);
            ASSERT_EQ(got, want) << isa << ": tile " << n << " at x " << x0 << ", " << width << "x" << height;
            streamed_tiles += x0 % 16 == 0 && width % 16 == 0;
        }
    }
    EXPECT_GT(streamed_tiles, 100);
}

// The same float, or both NaN: which NaN an operation returns when both of its operands are NaN
// depends on their order, which the compiler may swap; no output can tell NaNs apart.
bool same_float(float a, float b) {
    return std::memcmp(&a, &b, sizeof(float)) == 0 || (std::isnan(a) && std::isnan(b));
}

// What CompiledVertexStage<S>::run writes for vertices [0, n), in blocks of uneven sizes (every
// kernel's tail), must be what S::vertex() returns and writes for each vertex.
template <class S>
int expect_vertex_stage_is_vertex(const S& shader, std::size_t n, const std::string& isa) {
    constexpr int N = S::k_varyings;
    static_assert(detail::CompiledVertexStage<S>::available);
    std::vector<Vec4> clip(n);
    std::vector<float> varyings(n * N + 1);
    for (std::size_t begin = 0; begin < n; begin += 997) {
        const std::size_t end = std::min(n, begin + 997);
        detail::CompiledVertexStage<S>::run(shader, begin, end, clip.data() + begin, varyings.data() + begin * N);
    }
    int compared = 0;
    for (std::size_t i = 0; i < n; ++i) {
        Varyings<N> out;
        const Vec4 expected = shader.vertex(static_cast<std::uint32_t>(i), out);
        for (std::size_t k = 0; k < 4; ++k)
            EXPECT_TRUE(same_float(clip[i][k], expected[k])) << isa << ": vertex " << i << ", clip[" << k << "] "
                                                               << clip[i][k] << " != " << expected[k];
        for (int k = 0; k < N; ++k)
            EXPECT_TRUE(same_float(varyings[i * N + k], out[k])) << isa << ": vertex " << i << ", varying " << k;
        ++compared;
    }
    return compared;
}

TEST(Isa, CompiledVertexStagesEqualTheShadersVertexOnEveryIsa) {
    IsaGuard guard;
    const float specials[] = {0.0f, -0.0f, 1e-40f, 1e30f, -1e38f, std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()};
    std::mt19937 rng(20261122);
    std::uniform_real_distribution<float> any(-3.0f, 3.0f);
    std::uniform_int_distribution<int> kind(0, 19);
    auto value = [&] { return kind(rng) == 0 ? specials[rng() % std::size(specials)] : any(rng); };
    const std::size_t n = 5003;  // not a multiple of any vector
    Mesh mesh;
    for (std::size_t i = 0; i < n; ++i) {
        mesh.positions.push_back({value(), value(), value()});
        mesh.normals.push_back({value(), value(), value()});
        mesh.colours.push_back({any(rng), any(rng), any(rng), any(rng)});
    }
    Mesh bare;  // positions alone: no normals (a zero normal) and no colours (the base colour)
    bare.positions = mesh.positions;
    ShadingUniforms u;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) u.clip_from_object(r, c) = any(rng);
    u.clip_from_object(1, 2) = -0.0f;
    for (int c = 0; c < 3; ++c) u.normal_to_world.col[c] = {any(rng), any(rng), any(rng)};
    u.base_colour = {0.25f, 0.5f, 0.75f, 1.0f};
    int compared = 0;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        for (const Mesh* m : {&mesh, &bare}) {
            const MeshArrays arrays = MeshArrays::of(*m);
            compared += expect_vertex_stage_is_vertex(shaders::Lambert{arrays, u}, n, isa);
            compared += expect_vertex_stage_is_vertex(shaders::LambertBaseColour{arrays, u}, n, isa);
            compared += expect_vertex_stage_is_vertex(shaders::Normals{arrays, u}, n, isa);
            compared += expect_vertex_stage_is_vertex(shaders::VertexColour{arrays, u}, n, isa);
            compared += expect_vertex_stage_is_vertex(shaders::Mask{arrays, u}, n, isa);
        }
        if (HasFailure()) return;
    }
    EXPECT_EQ(compared, static_cast<int>(available_isas().size() * 10 * n));
}

}  // namespace
