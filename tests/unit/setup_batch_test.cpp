// Batched setup (setup_triangles, the SIMD kernel) against its specification, setup_triangle one
// triangle at a time, on every ISA this CPU runs: the same records byte for byte (zero-initialised on
// both sides, so padding compares too), in the same order, and the same culled count. Random triangles
// of every size and adversarial ones: zero area, every cull mode and winding, edges through pixel
// centres (the top-left rule), the guard band's extremes, coordinates too large for the kernel's exact
// doubles (its fallback), subnormal and huge q, scissors that leave nothing, partly filled batches,
// and batches of small triangles only (the kernel's 32-bit path).
// Also the front end as a whole: the same chunk (records, bins, statistics) on every ISA.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "facet/detail/front_end.hpp"
#include "facet/isa.hpp"
#include "geometry/project.hpp"
#include "setup/setup.hpp"
#include "support/pixels.hpp"
#include "support/reference_raster.hpp"

namespace {

using namespace facet;
using namespace facet::detail;

using facet_test::IsaGuard;

constexpr int k_guard = 16384 * k_subpixel_one;  // the guard band's extreme coordinate, fixed point

class Generator {
public:
    explicit Generator(std::uint32_t seed) : rng_(seed) {}

    FrontEndParams params() {
        FrontEndParams p{};
        const CullMode culls[] = {CullMode::none, CullMode::back, CullMode::front};
        p.state.cull = culls[pick(3)];
        p.state.front_face = pick(2) ? FrontFace::ccw : FrontFace::cw;
        switch (pick(4)) {
            case 0: p.scissor = {0, 0, 1920, 1080}; break;
            case 1: p.scissor = {0, 0, 8192, 8192}; break;
            case 2: {
                const int x0 = pick(600), y0 = pick(600);
                p.scissor = {x0, y0, x0 + 1 + pick(600), y0 + 1 + pick(600)};
                break;
            }
            default: p.scissor = {100, 100, 100 + pick(2), 100 + pick(2)}; break;  // empty or one pixel
        }
        p.vp_x = 0, p.vp_y = 0, p.vp_w = 1920, p.vp_h = 1080;
        p.tile_size = 64, p.tiles_x = 30, p.tiles_y = 17;
        return p;
    }

    void triangle(ScreenVertex (&v)[3]) {
        switch (pick(8)) {
            case 0: {  // anywhere in the guard band, any size
                for (ScreenVertex& s : v) s = vertex(coordinate(k_guard), coordinate(k_guard));
                break;
            }
            case 1: {  // small, near the scissor: pixel-sized or smaller
                const std::int32_t cx = coordinate(700 * k_subpixel_one), cy = coordinate(700 * k_subpixel_one);
                const std::int32_t r = 1 + pick(4 * k_subpixel_one);
                for (ScreenVertex& s : v) s = vertex(cx + coordinate(r), cy + coordinate(r));
                break;
            }
            case 2: {  // on pixel centres and half-pixel steps: edges through centres, axis-aligned edges
                for (ScreenVertex& s : v)
                    s = vertex(128 * (coordinate(40) + 8), 128 * (coordinate(40) + 8));
                break;
            }
            case 3: {  // zero area: repeated or collinear vertices
                v[0] = vertex(coordinate(k_guard), coordinate(k_guard));
                v[1] = pick(2) ? v[0] : vertex(coordinate(k_guard), coordinate(k_guard));
                const std::int32_t t = coordinate(4);
                v[2] = vertex(v[0].x + t * (v[1].x - v[0].x) / 4, v[0].y + t * (v[1].y - v[0].y) / 4);
                if (pick(2)) v[2] = v[1];
                break;
            }
            case 4: {  // corners of the guard band
                for (ScreenVertex& s : v) s = vertex(pick(2) ? k_guard : -k_guard, pick(3) ? k_guard : -k_guard);
                v[pick(3)].x = coordinate(k_guard);
                break;
            }
            case 5: {  // beyond the kernel's exact range (2^24): it must fall back to setup_triangle
                for (ScreenVertex& s : v) s = vertex(coordinate(1 << 27), coordinate(1 << 27));
                break;
            }
            case 6: {  // thin slivers
                v[0] = vertex(coordinate(k_guard), coordinate(k_guard));
                v[1] = vertex(v[0].x + coordinate(1 << 20), v[0].y + coordinate(2));
                v[2] = vertex(v[0].x + coordinate(1 << 20), v[0].y + coordinate(2));
                break;
            }
            default: {  // a mesh-like triangle of a few pixels on screen
                const std::int32_t cx = coordinate(1000 * k_subpixel_one) + 960 * k_subpixel_one;
                const std::int32_t cy = coordinate(600 * k_subpixel_one) + 540 * k_subpixel_one;
                for (ScreenVertex& s : v) s = vertex(cx + coordinate(1500), cy + coordinate(1500));
                break;
            }
        }
    }

    // Mostly triangles less than 64 pixels wide and tall (the kernel's 32-bit path takes batches of
    // those): pixel-sized ones near the scissor (sometimes cut by it), ones on pixel centres, zero
    // areas and mesh-like ones, in every winding; and a few up to 256 pixels across, past that
    // path's limit, where 32 bits would overflow.
    void small_triangle(ScreenVertex (&v)[3]) {
        if (pick(64) == 0) {
            const std::int32_t cx = coordinate(1000 * k_subpixel_one), cy = coordinate(1000 * k_subpixel_one);
            for (ScreenVertex& s : v) s = vertex(cx + coordinate(1 << 15), cy + coordinate(1 << 15));
            return;
        }
        switch (pick(4)) {
            case 0: {
                const std::int32_t cx = coordinate(700 * k_subpixel_one), cy = coordinate(700 * k_subpixel_one);
                const std::int32_t r = 1 + pick(16 * k_subpixel_one);
                for (ScreenVertex& s : v) s = vertex(cx + coordinate(r), cy + coordinate(r));
                break;
            }
            case 1: {
                for (ScreenVertex& s : v) s = vertex(128 * (coordinate(60) + 8), 128 * (coordinate(60) + 8));
                break;
            }
            case 2: {
                v[0] = vertex(coordinate(k_guard / 64), coordinate(k_guard / 64));
                v[1] = vertex(v[0].x + coordinate(4000), v[0].y + coordinate(4000));
                v[2] = pick(2) ? v[1] : v[0];
                break;
            }
            default: {
                const std::int32_t cx = coordinate(1000 * k_subpixel_one) + 960 * k_subpixel_one;
                const std::int32_t cy = coordinate(600 * k_subpixel_one) + 540 * k_subpixel_one;
                const std::int32_t r = pick(2) ? 1500 : 4000;  // 4000: up to 31 pixels across
                for (ScreenVertex& s : v) s = vertex(cx + coordinate(r), cy + coordinate(r));
                break;
            }
        }
    }

    std::uint32_t ref() { return static_cast<std::uint32_t>(rng_()); }

private:
    int pick(int n) { return static_cast<int>(rng_() % static_cast<std::uint32_t>(n)); }
    std::int32_t coordinate(std::int32_t r) {
        return std::uniform_int_distribution<std::int32_t>(-r, r)(rng_);
    }

    ScreenVertex vertex(std::int32_t x, std::int32_t y) { return {x, y, depth(), q()}; }

    float depth() {
        switch (pick(6)) {
            case 0: return 0.0f;
            case 1: return 1.0f;
            case 2: return -0.0f;  // std::clamp keeps a negative zero
            default: return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng_);
        }
    }

    float q() {
        switch (pick(8)) {
            case 0: return std::numeric_limits<float>::denorm_min() * static_cast<float>(1 + pick(1000));
            case 1: return std::numeric_limits<float>::min();
            case 2: return std::numeric_limits<float>::max() / static_cast<float>(1 + pick(4));
            case 3: return 1.0f;
            default: return std::exp2(std::uniform_real_distribution<float>(-40.0f, 40.0f)(rng_));
        }
    }

    std::mt19937 rng_;
};

struct Result {
    std::vector<TriangleSetup> records;
    int culled = 0;
};

Result set_up_one_by_one(const SetupBatch& batch, const FrontEndParams& p) {
    Result r;
    r.records.resize(static_cast<std::size_t>(batch.count));
    std::memset(static_cast<void*>(r.records.data()), 0, r.records.size() * sizeof(TriangleSetup));
    std::size_t written = 0;
    for (int i = 0; i < batch.count; ++i) {
        const ScreenVertex v[3] = {batch.v[0][i], batch.v[1][i], batch.v[2][i]};
        const std::uint32_t ref[3] = {batch.ref[0][i], batch.ref[1][i], batch.ref[2][i]};
        const SetupResult s = setup_triangle(v, ref, p, r.records[written]);
        written += s == SetupResult::ok;
        r.culled += s == SetupResult::culled;
    }
    r.records.resize(written);
    return r;
}

Result set_up_batch(const SetupBatch& batch, const FrontEndParams& p) {
    Result r;
    r.records.resize(static_cast<std::size_t>(batch.count));
    std::memset(static_cast<void*>(r.records.data()), 0, r.records.size() * sizeof(TriangleSetup));
    const BatchSetupCounts counts = setup_triangles(batch, p, r.records.data());
    r.records.resize(static_cast<std::size_t>(counts.written));
    r.culled = counts.culled;
    return r;
}

TEST(SetupBatch, EveryIsaWritesTheRecordsOfSetupTriangle) {
    IsaGuard guard;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        Generator gen(12345);
        SetupBatch batch{};
        std::size_t records = 0, mismatches = 0;
        for (int round = 0; round < 50000; ++round) {
            const FrontEndParams p = gen.params();
            // Mostly full batches; some partly filled ones over stale lanes of earlier batches.
            batch.count = round % 5 == 0 ? 1 + static_cast<int>(gen.ref() % SetupBatch::k_capacity)
                                         : SetupBatch::k_capacity;
            // Every third batch only small triangles, as a dense mesh gives them.
            const bool small_only = round % 3 == 1;
            for (int i = 0; i < batch.count; ++i) {
                ScreenVertex v[3];
                if (small_only)
                    gen.small_triangle(v);
                else
                    gen.triangle(v);
                for (int k = 0; k < 3; ++k) batch.v[k][i] = v[k], batch.ref[k][i] = gen.ref();
            }
            const Result want = set_up_one_by_one(batch, p);
            const Result got = set_up_batch(batch, p);
            ASSERT_EQ(got.culled, want.culled) << isa << " round " << round;
            ASSERT_EQ(got.records.size(), want.records.size()) << isa << " round " << round;
            for (std::size_t i = 0; i < want.records.size(); ++i)
                mismatches += std::memcmp(&got.records[i], &want.records[i], sizeof(TriangleSetup)) != 0;
            records += want.records.size();
        }
        EXPECT_EQ(mismatches, 0u) << isa;
        EXPECT_GT(records, 100000u) << isa;  // the comparison saw many surviving triangles
    }
}

// Each record's depth floor: every ISA's kernel gives lowest_depth of the record it writes, and that
// is the lowest depth_at over the record's bounds, attained there (exactly: no margin), or -infinity.
// Triangles of the generator's kinds with bounds up to 64 pixels, the depth checked at every pixel
// of the bounds.
TEST(SetupBatch, EachRecordsDepthFloorIsItsLowestDepthOverItsBounds) {
    IsaGuard guard;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        std::size_t checked = 0, sloped = 0;
        Generator gen(4242);
        SetupBatch batch{};
        SetupLanes lanes;
        for (int round = 0; round < 2000; ++round) {
            const FrontEndParams p = gen.params();
            batch.count = SetupBatch::k_capacity;
            for (int i = 0; i < batch.count; ++i) {
                ScreenVertex v[3];
                if (round % 2) gen.small_triangle(v);
                else gen.triangle(v);
                for (int k = 0; k < 3; ++k) batch.v[k][i] = v[k], batch.ref[k][i] = gen.ref();
            }
            if (!setup_lanes(batch, p, lanes)) continue;  // the scalar ISA: records one by one
            for (std::uint32_t keep = lanes.keep; keep != 0; keep &= keep - 1) {
                const int i = std::countr_zero(keep);
                TriangleSetup t;
                write_record(lanes, i, t);
                const float floor = lowest_depth(t);
                ASSERT_TRUE(lanes.floor[i] == floor || (std::isnan(floor) && std::isnan(lanes.floor[i])))
                    << isa << " round " << round << " lane " << i << ": " << lanes.floor[i] << " against " << floor;
                if (t.max_x - t.min_x > 64 || t.max_y - t.min_y > 64) continue;
                float lowest = std::numeric_limits<float>::infinity();
                for (int y = t.min_y; y <= t.max_y; ++y)
                    for (int x = t.min_x; x <= t.max_x; ++x) lowest = std::min(lowest, depth_at(t, x, y));
                if (floor == -std::numeric_limits<float>::infinity()) continue;
                ASSERT_EQ(floor, lowest) << isa << " round " << round << " lane " << i;
                ++checked;
                sloped += t.dzdx != 0 && t.dzdy != 0;
            }
        }
        if (isa == "scalar") continue;  // set up one by one: the floors are lowest_depth's own
        EXPECT_GT(checked, 2000u) << isa;
        EXPECT_GT(sloped, 2000u) << isa;
    }
}

// Triangles under 3 pixels across, whose bounds hold at most 3x3 pixel centres: setup_triangle
// keeps exactly those that cover a centre by the reference rasterizer's rule (the others are empty:
// never binned), and the batch kernels of every ISA keep the same ones.
TEST(SetupBatch, TrianglesOfSmallBoundsAreKeptExactlyWhenTheyCoverACentre) {
    namespace R = facet_test::raster;
    IsaGuard guard;
    std::mt19937 rng(777);
    const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    FrontEndParams p{};
    p.state.cull = CullMode::none;
    p.vp_x = 0, p.vp_y = 0, p.vp_w = 64, p.vp_h = 64;
    p.tile_size = 64, p.tiles_x = 1, p.tiles_y = 1;
    int kept = 0, empty = 0;
    SetupBatch batch{};
    for (int round = 0; round < 2000; ++round) {
        // Sometimes a scissor that cuts the bounds.
        p.scissor = pick(4) == 0 ? PixelRect{20 + pick(4), 20 + pick(4), 22 + pick(4), 22 + pick(4)} : PixelRect{0, 0, 64, 64};
        batch.count = SetupBatch::k_capacity;
        for (int i = 0; i < batch.count; ++i) {
            // On centres and half pixels often (edges through centres), else anywhere.
            const int step = pick(2) ? 128 : 1, extent = 3 * k_subpixel_one - 1;
            const std::int32_t ox = 20 * k_subpixel_one + pick(k_subpixel_one), oy = 20 * k_subpixel_one + pick(k_subpixel_one);
            ScreenVertex v[3];
            R::Fixed f[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = {ox + pick(extent / step + 1) * step, oy + pick(extent / step + 1) * step, 0.5f, 1.0f};
                f[k] = {v[k].x, v[k].y};
                batch.v[k][i] = v[k], batch.ref[k][i] = static_cast<std::uint32_t>(k);
            }
            // Every vertex is in pixels 20-23: the centres it can cover are there.
            int centres = 0;
            for (int y = std::max(p.scissor.y0, 19); y < std::min(p.scissor.y1, 25); ++y)
                for (int x = std::max(p.scissor.x0, 19); x < std::min(p.scissor.x1, 25); ++x)
                    centres += R::covers(f, R::pixel_centre(x, y));
            TriangleSetup t;
            const std::uint32_t ref[3] = {0, 1, 2};
            const SetupResult result = setup_triangle(v, ref, p, t);
            if (R::signed_area2(f[0], f[1], f[2]) == 0) {
                EXPECT_EQ(result, SetupResult::culled);
                continue;
            }
            ASSERT_EQ(result == SetupResult::ok, centres > 0) << "round " << round << " triangle " << i;
            kept += centres > 0;
            empty += centres == 0;
        }
        const Result want = set_up_one_by_one(batch, p);
        for (const std::string& isa : available_isas()) {
            ASSERT_TRUE(select_isa(isa));
            const Result got = set_up_batch(batch, p);
            ASSERT_EQ(got.records.size(), want.records.size()) << isa << " round " << round;
            for (std::size_t i = 0; i < want.records.size(); ++i)
                ASSERT_EQ(std::memcmp(&got.records[i], &want.records[i], sizeof(TriangleSetup)), 0) << isa << " round " << round;
        }
    }
    EXPECT_GT(kept, 5000);
    EXPECT_GT(empty, 2000);
}

// A whole front end over random geometry, some of it needing clipping (behind the eye, outside the
// guard band), so clipped triangles interleave with batches: same chunk on every ISA.
TEST(SetupBatch, TheFrontEndGivesTheSameChunkOnEveryIsa) {
    IsaGuard guard;
    FrontEndParams p{};
    p.state.cull = CullMode::back;
    p.scissor = {0, 0, 640, 480};
    p.vp_x = 0, p.vp_y = 0, p.vp_w = 640, p.vp_h = 480;
    p.tile_size = 32, p.tiles_x = 20, p.tiles_y = 15;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::size_t n = 30000;
    ClipVertices vertices;
    vertices.resize(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const bool far_out = rng() % 50 == 0;
        const float w = rng() % 100 == 0 ? -0.5f : 1.0f + u(rng) * 0.5f;
        const float s = far_out ? 4000.0f : 1.0f;
        vertices.pos[i] = {u(rng) * w * s, u(rng) * w * s, (u(rng) * 0.5f + 0.5f) * w, w};
    }
    std::vector<std::uint32_t> indices;
    for (std::size_t t = 0; t < 40000; ++t) {
        const std::uint32_t a = static_cast<std::uint32_t>(rng() % n);
        indices.insert(indices.end(), {a, static_cast<std::uint32_t>((a + 1 + rng() % 8) % n),
                                       static_cast<std::uint32_t>((a + 1 + rng() % 8) % n)});
    }
    const DrawInput input{static_cast<std::uint32_t>(n), indices};

    auto run = [&](const std::string& isa) {
        EXPECT_TRUE(select_isa(isa));
        ClipVertices v = vertices;
        project_vertices(v, 0, n, p);
        FrontEndChunk chunk;
        chunk.reset(static_cast<std::size_t>(p.tiles_x * p.tiles_y), 0);
        run_front_end(v, input, 0, indices.size() / 3, p, chunk);
        return chunk;
    };
    const FrontEndChunk want = run("scalar");
    EXPECT_GT(want.stats.triangles_clipped, 0u);
    EXPECT_GT(want.stats.triangles_culled, 0u);
    EXPECT_GT(want.stats.triangles_rasterized, 1000u);
    std::size_t small = 0, large = 0, pieces = 0;  // records of each kind, and pieces, compared
    for (const std::string& isa : available_isas()) {
        const FrontEndChunk got = run(isa);
        ASSERT_EQ(got.bins.size(), want.bins.size()) << isa;
        for (std::size_t tile = 0; tile < want.bins.size(); ++tile) {
            ASSERT_EQ(got.bins[tile].size(), want.bins[tile].size()) << isa << " tile " << tile;
            for (std::size_t i = 0; i < want.bins[tile].size(); ++i) {
                // Records not zero-initialised here: compare the fields, not the padding.
                const TriangleSetup &g = got.bins[tile][i], &w = want.bins[tile][i];
                ASSERT_EQ(std::memcmp(&g, &w, offsetof(TriangleSetup, front_facing)), 0)
                    << isa << " tile " << tile << " record " << i;
                ASSERT_EQ(g.front_facing, w.front_facing) << isa << " tile " << tile << " record " << i;
                ASSERT_EQ(g.small_edges, w.small_edges) << isa << " tile " << tile << " record " << i;
                small += g.small_edges;
                large += !g.small_edges;
            }
            // The depth floors (a depth test less): per piece the lowest of its records' floors.
            ASSERT_EQ(got.depth_floors[tile].size(), (want.bins[tile].size() + k_bin_piece - 1) / k_bin_piece) << isa;
            for (std::size_t piece = 0; piece < got.depth_floors[tile].size(); ++piece) {
                float lowest = std::numeric_limits<float>::infinity();
                for (std::size_t i = piece * k_bin_piece; i < std::min(want.bins[tile].size(), (piece + 1) * k_bin_piece); ++i)
                    lowest = std::min(lowest, lowest_depth(want.bins[tile][i]));
                ASSERT_EQ(got.depth_floors[tile][piece], lowest) << isa << " tile " << tile << " piece " << piece;
                pieces += 1;
            }
        }
        EXPECT_EQ(got.stats.triangles_culled, want.stats.triangles_culled) << isa;
        EXPECT_EQ(got.stats.triangles_rasterized, want.stats.triangles_rasterized) << isa;
        EXPECT_EQ(got.stats.triangles_clipped, want.stats.triangles_clipped) << isa;
    }
    EXPECT_GT(small, 1000u);
    EXPECT_GT(large, 10u);
    EXPECT_GT(pieces, 300u);
}

}  // namespace
