// Property: points and lines cover the pixels their rules (README.md, "Points and lines") say, checked
// against brute-force references written from the rules alone: a round point covers the pixel
// centres within size / 2 of its snapped centre, a square one those inside its square (left and top
// edges included); a segment those within width / 2 of it between its ends (up to the 1/256-pixel
// snapping of its corners), and strips meet without gaps or double hits. Depth against triangles,
// clipping, bad input, and the same bytes over threads, tile sizes and ISAs.
//
// Centres are placed exactly on the 1/256-pixel grid: on a 64x64 target with w = 1, clip x = X / 8192 - 1
// is exact in float and projects to X / 256 pixels, so the test knows the snapped centre without
// repeating the projection's arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "facet/error.hpp"
#include "facet/isa.hpp"
#include "facet/renderer.hpp"

namespace {

using namespace facet;

constexpr int k_size = 64;

// Clip position of the fixed-point screen position (X, Y) (1/256 pixel) on the 64x64 target, at depth z.
Vec4 clip_at(std::int32_t X, std::int32_t Y, float z = 0.5f) {
    return {static_cast<float>(X) / 8192.0f - 1.0f, 1.0f - static_cast<float>(Y) / 8192.0f, z, 1.0f};
}

// Counts every fragment of a draw per pixel (depth test always, so every covered pixel is shaded once
// per primitive triangle covering it).
struct CountingShader {
    static constexpr int k_varyings = 0;
    static constexpr bool k_shade_hidden = true;
    const std::vector<Vec4>* pos;
    std::vector<std::atomic<int>>* hits;
    Vec4 vertex(std::uint32_t i, Varyings<0>&) const { return (*pos)[i]; }
    Vec4 fragment(const FragmentIn<0>& in) const {
        const int x = static_cast<int>(in.pos_screen.x), y = static_cast<int>(in.pos_screen.y);
        (*hits)[static_cast<std::size_t>(y) * k_size + x].fetch_add(1, std::memory_order_relaxed);
        return Vec4{1, 1, 1, 1};
    }
};

struct Hits {
    std::vector<int> count;
    DrawStats stats;
};

Hits draw_counting(const std::vector<Vec4>& pos, const std::vector<std::uint32_t>& indices, Topology topology,
                   PrimitiveStyle style, RendererConfig config = {.threads = 2, .tile_size = 16}) {
    Renderer renderer(config);
    Framebuffer fb(k_size, k_size);
    std::vector<std::atomic<int>> hits(k_size * k_size);
    const CountingShader shader{&pos, &hits};
    DrawState state;
    state.depth_test = DepthTest::always;
    state.depth_write = false;
    state.clear = ClearValues{};
    DrawInput input{static_cast<std::uint32_t>(pos.size()), indices, topology, style};
    Hits out;
    out.stats = renderer.draw(fb, state, input, shader);
    for (auto& h : hits) out.count.push_back(h.load());
    return out;
}

std::int64_t centre(int pixel) { return std::int64_t{pixel} * 256 + 128; }

TEST(Points, RoundPointsCoverThePixelCentresWithinTheirRadius) {
    std::mt19937 rng(26);
    std::uniform_int_distribution<std::int32_t> coordinate(-8 * 256, 72 * 256);
    std::uniform_real_distribution<float> size(0.25f, 24.0f);
    int covered = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const std::int32_t X = coordinate(rng), Y = coordinate(rng);
        const float s = trial < 20 ? static_cast<float>(trial + 1) : size(rng);  // whole sizes too: ties
        const Hits h = draw_counting({clip_at(X, Y)}, {}, Topology::points, {.point_size = s});
        const double r = static_cast<double>(s) * 128.0;
        for (int y = 0; y < k_size; ++y)
            for (int x = 0; x < k_size; ++x) {
                const double dx = static_cast<double>(centre(x) - X), dy = static_cast<double>(centre(y) - Y);
                const int expected = dx * dx + dy * dy <= r * r ? 1 : 0;
                covered += expected;
                ASSERT_EQ(h.count[y * k_size + x], expected)
                    << "pixel " << x << "," << y << " of a point at " << X / 256.0 << "," << Y / 256.0 << " size " << s;
            }
        EXPECT_EQ(h.stats.points_in, 1u);
    }
    EXPECT_GT(covered, 10000);
}

TEST(Points, SquarePointsCoverTheirSquareLeftAndTopEdgesIncluded) {
    std::mt19937 rng(27);
    std::uniform_int_distribution<std::int32_t> coordinate(-8 * 256, 72 * 256);
    std::uniform_real_distribution<float> size(0.25f, 24.0f);
    int covered = 0;
    for (int trial = 0; trial < 300; ++trial) {
        // Half of them on pixel corners and centres with whole sizes, where the edges pass through centres.
        const bool grid = trial % 2 == 0;
        const std::int32_t X = grid ? coordinate(rng) / 128 * 128 : coordinate(rng);
        const std::int32_t Y = grid ? coordinate(rng) / 128 * 128 : coordinate(rng);
        const float s = grid ? static_cast<float>(1 + trial % 9) : size(rng);
        const Hits h = draw_counting({clip_at(X, Y)}, {}, Topology::points, {.point_size = s, .point_shape = PointShape::square});
        const std::int64_t half = std::llround(static_cast<double>(s) * 128.0);
        for (int y = 0; y < k_size; ++y)
            for (int x = 0; x < k_size; ++x) {
                const bool in_x = X - half <= centre(x) && centre(x) < X + half;
                const bool in_y = Y - half <= centre(y) && centre(y) < Y + half;
                const int expected = in_x && in_y ? 1 : 0;
                covered += expected;
                ASSERT_EQ(h.count[y * k_size + x], expected)
                    << "pixel " << x << "," << y << " of a point at " << X / 256.0 << "," << Y / 256.0 << " size " << s;
            }
    }
    EXPECT_GT(covered, 10000);
}

// Distance from pixel centre (x, y) to the segment's band: negative inside (within w/2 of the line and
// between the ends), in pixels; `margin` is how far the pixel centre is from the band's boundary.
struct Band {
    double ax, ay, bx, by, h;
    // Signed distance to the rectangle's boundary (negative inside).
    double signed_distance(double px, double py) const {
        const double dx = bx - ax, dy = by - ay, length = std::sqrt(dx * dx + dy * dy);
        const double ux = dx / length, uy = dy / length;
        const double along = (px - ax) * ux + (py - ay) * uy, across = std::abs(-(px - ax) * uy + (py - ay) * ux);
        const double out_along = std::max(-along, along - length), out_across = across - h;
        if (out_along <= 0 || out_across <= 0) return std::max(out_along, out_across);
        return std::hypot(out_along, out_across);
    }
};

TEST(Lines, SegmentsCoverThePixelCentresWithinHalfTheirWidth) {
    std::mt19937 rng(28);
    std::uniform_int_distribution<std::int32_t> coordinate(-16 * 256, 80 * 256);
    std::uniform_real_distribution<float> width(0.5f, 12.0f);
    int covered = 0, undecided = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const std::int32_t X0 = coordinate(rng), Y0 = coordinate(rng), X1 = coordinate(rng), Y1 = coordinate(rng);
        if (X0 == X1 && Y0 == Y1) continue;
        const float w = trial < 30 ? 1.0f : width(rng);
        const Hits h = draw_counting({clip_at(X0, Y0), clip_at(X1, Y1)}, {}, Topology::lines, {.line_width = w});
        const Band band{X0 / 256.0, Y0 / 256.0, X1 / 256.0, Y1 / 256.0, w / 2.0};
        for (int y = 0; y < k_size; ++y)
            for (int x = 0; x < k_size; ++x) {
                const double d = band.signed_distance(x + 0.5, y + 0.5);
                const int count = h.count[y * k_size + x];
                ASSERT_LE(count, 1) << "pixel " << x << "," << y << " drawn twice, trial " << trial;
                // The corners are snapped to 1/256 pixel: only centres that close to the boundary may go either way.
                if (std::abs(d) < 1.0 / 128) {
                    ++undecided;
                    continue;
                }
                ASSERT_EQ(count, d < 0 ? 1 : 0) << "pixel " << x << "," << y << " at " << d << " px from the band's edge, trial "
                                                << trial << " width " << w;
                covered += count;
            }
        EXPECT_EQ(h.stats.segments_in, 1u);
    }
    EXPECT_GT(covered, 10000);
    EXPECT_LT(undecided, covered / 100);
}

// A random polyline drawn as a list of segments sharing their ends (indices 0 1 1 2 2 3 ...): every
// pixel at most once, every pixel centre within w/2 of the polyline drawn (no gaps at the joins), and
// nothing further than the mitre reaches.
TEST(Lines, StripsJoinWithoutGapsOrDoubleHits) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int joins = 0, covered = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const double w = 1.0 + 7.0 * unit(rng), h = w / 2;
        const double length = 6 * h + 4 + 8 * unit(rng);
        double x = 8 + 48 * unit(rng), y = 8 + 48 * unit(rng), heading = 6.2832 * unit(rng);
        std::vector<Vec4> pos;
        std::vector<std::pair<double, double>> snapped;
        for (int k = 0; k < 8; ++k) {
            const auto X = static_cast<std::int32_t>(std::lround(x * 256)), Y = static_cast<std::int32_t>(std::lround(y * 256));
            pos.push_back(clip_at(X, Y));
            snapped.emplace_back(X / 256.0, Y / 256.0);
            heading += (unit(rng) - 0.5) * 2 * 2.0;  // turns of up to about 115 degrees
            x += length * std::cos(heading), y += length * std::sin(heading);
        }
        std::vector<std::uint32_t> indices;
        for (std::uint32_t k = 0; k + 1 < pos.size(); ++k) indices.insert(indices.end(), {k, k + 1});
        joins += static_cast<int>(pos.size()) - 2;
        const Hits hits = draw_counting(pos, indices, Topology::lines, {.line_width = static_cast<float>(w)});
        for (int py = 0; py < k_size; ++py)
            for (int px = 0; px < k_size; ++px) {
                double nearest = 1e30;
                // A random polyline may cross itself: there, two segments that do not meet at a join
                // both cover the pixel, and a double hit is right.
                std::vector<std::size_t> reaching;
                for (std::size_t k = 0; k + 1 < snapped.size(); ++k) {
                    const Band band{snapped[k].first, snapped[k].second, snapped[k + 1].first, snapped[k + 1].second, h};
                    const double d = band.signed_distance(px + 0.5, py + 0.5);
                    nearest = std::min(nearest, d);
                    if (d < 2 * h + 1) reaching.push_back(k);
                }
                const bool crossing = reaching.size() >= 2 && reaching.back() - reaching.front() >= 2;
                const int count = hits.count[py * k_size + px];
                if (crossing) continue;
                ASSERT_LE(count, 1) << "pixel " << px << "," << py << " drawn twice, trial " << trial;
                if (nearest < -1.0 / 64) {
                    ASSERT_EQ(count, 1) << "gap at " << px << "," << py << ", trial " << trial;
                }
                if (count) {
                    EXPECT_LT(nearest, 2 * h) << "stray pixel " << px << "," << py << ", trial " << trial;
                }
                covered += count;
            }
    }
    EXPECT_GT(joins, 300);
    EXPECT_GT(covered, 10000);
}

// Closed polygons drawn as lists of segments whose last ends where the first begins (a loop), placed
// between two unrelated segments: the closing join is mitred like the others, so every pixel of the
// outline is drawn exactly once, with no gap or double hit at any corner.
TEST(Lines, LoopsCloseWithAJoinWithoutGapsOrDoubleHits) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int corners = 0, covered = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const int n = 3 + trial % 6;
        const double w = 1.0 + 6.0 * unit(rng), h = w / 2, radius = 12 + 12 * unit(rng), turn = 6.2832 * unit(rng);
        std::vector<Vec4> pos = {clip_at(2 * 256, 2 * 256), clip_at(6 * 256, 3 * 256)};  // an unrelated segment
        std::vector<std::pair<double, double>> snapped;
        for (int k = 0; k < n; ++k) {
            const double a = turn + 6.2832 * k / n;
            const auto X = static_cast<std::int32_t>(std::lround((32 + radius * std::cos(a)) * 256));
            const auto Y = static_cast<std::int32_t>(std::lround((32 + radius * std::sin(a)) * 256));
            pos.push_back(clip_at(X, Y));
            snapped.emplace_back(X / 256.0, Y / 256.0);
        }
        pos.push_back(clip_at(58 * 256, 60 * 256)), pos.push_back(clip_at(61 * 256, 57 * 256));
        std::vector<std::uint32_t> indices = {0, 1};
        for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(n); ++k)
            indices.insert(indices.end(), {2 + k, 2 + (k + 1) % static_cast<std::uint32_t>(n)});
        const auto last = static_cast<std::uint32_t>(pos.size());
        indices.insert(indices.end(), {last - 2, last - 1});
        corners += n;
        const Hits hits = draw_counting(pos, indices, Topology::lines, {.line_width = static_cast<float>(w)});
        for (int py = 8; py < 56; ++py)  // the polygon's pixels, away from the two other segments
            for (int px = 8; px < 56; ++px) {
                double nearest = 1e30;
                for (int k = 0; k < n; ++k) {
                    const auto& [ax, ay] = snapped[static_cast<std::size_t>(k)];
                    const auto& [bx, by] = snapped[static_cast<std::size_t>((k + 1) % n)];
                    nearest = std::min(nearest, Band{ax, ay, bx, by, h}.signed_distance(px + 0.5, py + 0.5));
                }
                const int count = hits.count[py * k_size + px];
                ASSERT_LE(count, 1) << "pixel " << px << "," << py << " drawn twice, trial " << trial << ", " << n << " sides";
                if (nearest < -1.0 / 64) {
                    ASSERT_EQ(count, 1) << "gap at " << px << "," << py << ", trial " << trial;
                }
                if (count) {
                    EXPECT_LT(nearest, 2 * h) << "stray pixel " << px << "," << py << ", trial " << trial;
                }
                covered += count;
            }
        EXPECT_EQ(hits.stats.segments_in, static_cast<std::uint64_t>(n) + 2);
    }
    EXPECT_GT(corners, 150);
    EXPECT_GT(covered, 5000);
}

// Each segment is one record (raster/segment.hpp), binned to the tiles it crosses, and both drawing
// orders cover the same pixels with it: the one-pass order (CountingShader, the coverage kernel) and
// the visible-only order (the depth pass), over tile sizes, with segments of 0.5 to 12 pixels' width
// from within a pixel to past the target.
TEST(Lines, EachSegmentIsOneRecordCoveringTheSamePixelsInBothOrders) {
    std::mt19937 rng(32);
    std::uniform_int_distribution<std::int32_t> coordinate(-16 * 256, 80 * 256), near(-3 * 256, 3 * 256);
    std::uniform_real_distribution<float> width(0.5f, 12.0f);
    std::vector<Vec4> pos;
    for (int k = 0; k < 60; ++k) {
        const std::int32_t X = coordinate(rng), Y = coordinate(rng);
        const bool short_one = k % 3 == 0;
        std::int32_t X1 = short_one ? X + near(rng) : coordinate(rng), Y1 = short_one ? Y + near(rng) : coordinate(rng);
        if (X1 == X && Y1 == Y) ++X1;
        pos.push_back(clip_at(X, Y)), pos.push_back(clip_at(X1, Y1));
    }
    const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    for (int trial = 0; trial < 10; ++trial) {
        const PrimitiveStyle style{.line_width = width(rng)};
        for (int tile : {8, 16, 64}) {
            const RendererConfig config{.threads = 2, .tile_size = tile};
            const Hits hits = draw_counting(pos, {}, Topology::lines, style, config);
            Renderer renderer(config);
            Framebuffer fb(k_size, k_size);
            DrawState state;
            state.clear = ClearValues{};
            const DrawStats stats = renderer.draw(fb, state, {static_cast<std::uint32_t>(pos.size()), {}, Topology::lines, style}, shader);
            // One record per segment that reaches the target (over 30 of the 60 do): two triangles each would pass 60.
            EXPECT_EQ(stats.triangles_rasterized, hits.stats.triangles_rasterized);
            EXPECT_LE(stats.triangles_rasterized, 60u);
            EXPECT_GT(stats.triangles_rasterized, 30u);
            int covered = 0;
            for (int i = 0; i < k_size * k_size; ++i) {
                covered += hits.count[i] > 0;
                ASSERT_EQ(fb.colour_data()[i].r == 255, hits.count[i] > 0)
                    << "pixel " << i % k_size << "," << i / k_size << ", tiles " << tile << ", width " << style.line_width;
            }
            EXPECT_GT(covered, 300);
        }
    }
}

// A point or a line on a surface's depth: in front of the surface it wins, behind it loses.
TEST(PointsAndLines, AreDepthTestedAgainstTriangles) {
    std::vector<Vec4> pos = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {1, 1, 0, 1}, {-1, 1, 0, 1}};  // z set below
    std::vector<Vec4> colour = {{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}};
    for (Vec4& p : pos) p.z = 0.5f;
    const std::uint32_t quad[] = {0, 1, 2, 0, 2, 3};
    // Points at 16,16 (in front: z 0.4) and 48,48 (behind: z 0.6); a line in front along row 8 and behind along row 56.
    const std::uint32_t first = static_cast<std::uint32_t>(pos.size());
    for (auto [X, Y, z] : {std::tuple{16, 16, 0.4f}, {48, 48, 0.6f}, {4, 8, 0.4f}, {60, 8, 0.4f}, {4, 56, 0.6f}, {60, 56, 0.6f}}) {
        pos.push_back(clip_at(X * 256, Y * 256, z));
        colour.push_back({0, 1, 0, 1});
    }
    const auto shader = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, colour[i]);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    for (int threads : {1, 2}) {
        Renderer renderer({.threads = threads, .tile_size = 16});
        Framebuffer fb(k_size, k_size);
        DrawState state;
        state.clear = ClearValues{};
        renderer.draw(fb, state, {static_cast<std::uint32_t>(pos.size()), quad}, shader);
        state.clear.reset();
        const std::uint32_t points[] = {first, first + 1}, lines[] = {first + 2, first + 3, first + 4, first + 5};
        const DrawStats ps = renderer.draw(fb, state, {static_cast<std::uint32_t>(pos.size()), points, Topology::points, {.point_size = 5}}, shader);
        const DrawStats ls = renderer.draw(fb, state, {static_cast<std::uint32_t>(pos.size()), lines, Topology::lines, {.line_width = 3}}, shader);
        EXPECT_EQ(ps.points_in, 2u);
        EXPECT_EQ(ls.segments_in, 2u);
        EXPECT_EQ(fb.colour(16, 16).g, 255) << "the point in front wins";
        EXPECT_EQ(fb.colour(16, 16).r, 0);
        EXPECT_FLOAT_EQ(fb.depth(16, 16), 0.4f);
        EXPECT_EQ(fb.colour(48, 48).r, 255) << "the point behind loses";
        EXPECT_EQ(fb.colour(48, 48).g, 0);
        EXPECT_FLOAT_EQ(fb.depth(48, 48), 0.5f);
        EXPECT_EQ(fb.colour(32, 8).g, 255) << "the line in front wins";
        EXPECT_EQ(fb.colour(32, 56).r, 255) << "the line behind loses";
        EXPECT_EQ(fb.colour(32, 32).r, 255);
    }
}

// Varyings reach a point's pixels unchanged, and along a line they are interpolated between its ends.
TEST(PointsAndLines, CarryTheirVertexAttributes) {
    const std::vector<Vec4> pos = {clip_at(20 * 256, 20 * 256), clip_at(8 * 256 + 128, 40 * 256 + 128),
                                   clip_at(56 * 256 + 128, 40 * 256 + 128)};
    const std::vector<Vec4> colour = {{0.2f, 0.4f, 0.6f, 1}, {1, 0, 0, 1}, {0, 0, 1, 1}};
    const auto shader = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, colour[i]);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    Renderer renderer({.threads = 1});
    Framebuffer fb(k_size, k_size);
    DrawState state;
    state.clear = ClearValues{};
    const std::uint32_t point[] = {0}, line[] = {1, 2};
    renderer.draw(fb, state, {3, point, Topology::points, {.point_size = 6}}, shader);
    state.clear.reset();
    renderer.draw(fb, state, {3, line, Topology::lines, {.line_width = 1}}, shader);
    for (int y = 17; y < 23; ++y)
        for (int x = 17; x < 23; ++x)
            if (fb.colour(x, y).a) {
                EXPECT_EQ((std::array{fb.colour(x, y).r, fb.colour(x, y).g, fb.colour(x, y).b}),
                          (std::array<std::uint8_t, 3>{51, 102, 153}));
            }
    EXPECT_GT(fb.colour(10, 40).r, 200);
    EXPECT_LT(fb.colour(10, 40).b, 50);
    EXPECT_GT(fb.colour(54, 40).b, 200);
    EXPECT_NEAR(fb.colour(32, 40).r, 127, 2);
}

TEST(PointsAndLines, InvalidOnesAreDroppedAndCountedAndBadSizesRefused) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<Vec4> pos = {clip_at(20 * 256, 20 * 256), {nan, 0, 0.5f, 1}, clip_at(40 * 256, 40 * 256),
                                   {0, 0, 0.5f, -1} /* behind the eye */, {0, 0, 2, 1} /* past far */};
    const std::vector<std::uint32_t> points = {0, 1, 2, 7, 3, 4};
    Hits h = draw_counting(pos, points, Topology::points, {.point_size = 3});
    EXPECT_EQ(h.stats.points_in, 6u);
    EXPECT_EQ(h.stats.points_invalid, 2u);  // NaN and index 7
    int drawn = 0;
    for (int c : h.count) drawn += c;
    EXPECT_EQ(drawn, 2 * 4);  // two points of size 3 on pixel corners: the 4 centres at 0.71 px
    const std::vector<std::uint32_t> lines = {0, 1, 0, 2, 9, 2, 2, 3, 3, 4};
    h = draw_counting(pos, lines, Topology::lines, {.line_width = 2});
    EXPECT_EQ(h.stats.segments_in, 5u);
    EXPECT_EQ(h.stats.segments_invalid, 2u);  // NaN end and index 9
    EXPECT_GT(h.stats.triangles_clipped, 0u);  // 2-3 crosses the near plane and is cut
    for (float bad : {0.0f, -1.0f, nan, 257.0f, 1e30f, std::numeric_limits<float>::infinity()}) {
        EXPECT_THROW(draw_counting(pos, points, Topology::points, {.point_size = bad}), FacetError) << bad;
        EXPECT_THROW(draw_counting(pos, lines, Topology::lines, {.line_width = bad}), FacetError) << bad;
    }
    EXPECT_THROW(draw_counting(pos, points, Topology::points, {.point_size = 1, .model_scale = nan}), FacetError);
    EXPECT_THROW(draw_counting(pos, points, Topology::points, {.point_size = 1, .model_scale = -2}), FacetError);
}

// Sizes in model units shrink with distance: size * model_scale / w pixels.
TEST(Points, ModelUnitSizesArePerspectiveScaled) {
    std::vector<Vec4> pos = {{-0.5f, 0, 0.5f, 1}, {1.0f, 0, 1.0f, 2}};  // the second at w = 2, x = 0.5 after division
    const std::uint32_t first[] = {0}, second[] = {1};
    const Hits near = draw_counting(pos, {first[0]}, Topology::points, {.point_size = 0.25f, .model_scale = 64});
    const Hits far = draw_counting(pos, {second[0]}, Topology::points, {.point_size = 0.25f, .model_scale = 64});
    const Hits pixels16 = draw_counting(pos, {first[0]}, Topology::points, {.point_size = 16});
    const Hits pixels8 = draw_counting(pos, {second[0]}, Topology::points, {.point_size = 8});
    EXPECT_EQ(near.count, pixels16.count);
    EXPECT_EQ(far.count, pixels8.count);
}

// A size in model units may exceed 256: the point drawn is capped at 256 pixels, also where the
// size times the scale is too large for a float. Sizes that are not in (0, 1e30) are refused.
TEST(Points, ModelUnitSizesAboveTheLimitAreDrawnAtTheLimit) {
    // The centre 100 pixels left of the 64-pixel target (inside the guard band), so that only the
    // disc's right part reaches the target and its size shows.
    std::vector<Vec4> pos = {{-4.125f, 0.1f, 0.5f, 1}};
    const std::uint32_t point[] = {0};
    const Hits largest = draw_counting(pos, {point[0]}, Topology::points, {.point_size = PrimitiveStyle::k_max_point_size});
    const Hits smaller = draw_counting(pos, {point[0]}, Topology::points, {.point_size = 250});
    ASSERT_NE(largest.count, smaller.count);
    for (float units : {300.0f, 1e6f, 9e29f}) {
        const Hits h = draw_counting(pos, {point[0]}, Topology::points, {.point_size = units, .model_scale = 1e20f});
        EXPECT_EQ(h.count, largest.count) << units;
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (float bad : {0.0f, -1.0f, nan, 1e30f, std::numeric_limits<float>::infinity()})
        EXPECT_THROW(draw_counting(pos, {point[0]}, Topology::points, {.point_size = bad, .model_scale = 4}), FacetError) << bad;
}

// A draw is cut into chunks by segment index, more of them with more threads (2048 segments or more
// make two chunks at one thread): lone segments (a line list's, which the front end queues in a loop of
// their own), strips and loops through the chunks' boundaries, repeated and out-of-range indices,
// segments of no length and ones crossing the near plane, mixed, give the same bytes and counts
// whatever the chunks.
TEST(Lines, ListsStripsAndLoopsMixedGiveTheSameBytesWhateverTheChunks) {
    std::mt19937 rng(32);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f), c(0, 1);
    std::vector<Vec4> pos, colour;
    std::vector<std::uint32_t> indices;
    const auto vertex = [&](float w) {
        pos.push_back({u(rng) * w, u(rng) * w, c(rng) * w, w});
        colour.push_back({c(rng), c(rng), c(rng), 1});
        return static_cast<std::uint32_t>(pos.size() - 1);
    };
    std::uint64_t invalid = 0;
    while (indices.size() < 2 * 9000) {
        const int kind = static_cast<int>(c(rng) * 8);
        if (kind <= 2) {  // lone segments
            for (int k = 0; k < 1 + kind * 20; ++k) indices.insert(indices.end(), {vertex(1), vertex(1)});
        } else if (kind <= 4) {  // a strip, or a loop when kind is 4
            const int n = 2 + static_cast<int>(c(rng) * 40);
            const std::uint32_t start = vertex(1);
            std::uint32_t at = start;
            for (int k = 0; k < n; ++k) {
                const std::uint32_t next = kind == 4 && k + 1 == n ? start : vertex(1);
                indices.insert(indices.end(), {at, next});
                at = next;
            }
        } else if (kind == 5) {  // no length: both ends the same vertex
            const std::uint32_t v = vertex(1);
            indices.insert(indices.end(), {v, v});
        } else if (kind == 6) {  // an end out of range, first or second
            const std::uint32_t v = vertex(1);
            const bool first = c(rng) < 0.5f;
            indices.insert(indices.end(), {first ? 0xfffffff0u : v, first ? v : 0xfffffff0u});
            ++invalid;
        } else {  // through the near plane (w of one end negative): clipped
            const std::uint32_t a = vertex(1), b = vertex(-0.5f);
            indices.insert(indices.end(), {a, b});
        }
    }
    const auto shader = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, colour[i]);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    const auto render = [&](int threads, DrawStats& stats) {
        Renderer renderer({.threads = threads, .tile_size = 16});
        Framebuffer fb(96, 80);
        DrawState state;
        state.clear = ClearValues{};
        stats = renderer.draw(fb, state, {static_cast<std::uint32_t>(pos.size()), indices, Topology::lines, {.line_width = 2.5f}}, shader);
        std::vector<std::uint32_t> bytes(2 * 96 * 80);
        std::memcpy(bytes.data(), fb.colour_data(), 96 * 80 * sizeof(Rgba8));
        std::memcpy(bytes.data() + 96 * 80, fb.depth_data(), 96 * 80 * sizeof(float));
        return bytes;
    };
    DrawStats reference_stats;
    const auto reference = render(1, reference_stats);
    EXPECT_EQ(reference_stats.segments_in, indices.size() / 2);
    EXPECT_EQ(reference_stats.segments_invalid, invalid);
    EXPECT_GT(reference_stats.triangles_clipped, 50u);
    for (int threads : {2, 3, 5}) {
        DrawStats stats;
        EXPECT_EQ(render(threads, stats), reference) << threads << " threads";
        EXPECT_EQ(stats.segments_invalid, invalid);
        EXPECT_EQ(stats.triangles_rasterized, reference_stats.triangles_rasterized) << threads << " threads";
    }
}

// The same bytes for any thread count, tile size and ISA: a few thousand points and segments of all
// sizes, aliased and anti-aliased, overlapping, through clipping and across tiles.
TEST(PointsAndLines, SameBytesOverThreadsTilesAndIsas) {
    std::mt19937 rng(30);
    std::uniform_real_distribution<float> u(-1.3f, 1.3f), z(-0.1f, 1.1f), c(0, 1);
    std::vector<Vec4> pos, colour;
    for (int i = 0; i < 4000; ++i) {
        const float w = 0.5f + c(rng) * 2;
        pos.push_back({u(rng) * w, u(rng) * w, z(rng) * w, w});
        colour.push_back({c(rng), c(rng), c(rng), i % 3 == 0 ? 0.5f : 1.0f});
    }
    std::vector<std::uint32_t> strip;
    for (std::uint32_t i = 0; i + 1 < 600; ++i) strip.insert(strip.end(), {i, i + 1});
    const auto shader = make_shader<4>(
        [&](std::uint32_t i, Varyings<4>& out) {
            out.set(0, colour[i]);
            return pos[i];
        },
        [](const FragmentIn<4>& in) { return in.v.vec4(0); });
    const auto render = [&](int threads, int tile) {
        Renderer renderer({.threads = threads, .tile_size = tile});
        Framebuffer fb(301, 203);
        DrawState state;
        state.clear = ClearValues{};
        const auto n = static_cast<std::uint32_t>(pos.size());
        renderer.draw(fb, state, {n, {}, Topology::points, {.point_size = 7}}, shader);
        state.clear.reset();
        renderer.draw(fb, state, {n, {}, Topology::points, {.point_size = 3, .point_shape = PointShape::square}}, shader);
        renderer.draw(fb, state, {n, {}, Topology::points, {.point_size = 0.05f, .model_scale = 100}}, shader);
        renderer.draw(fb, state, {n, {}, Topology::lines, {.line_width = 1.5f}}, shader);
        renderer.draw(fb, state, {n, strip, Topology::lines, {.line_width = 4}}, shader);
        // Anti-aliased (blended, over what is drawn): the colours' alphas are 1, a third of them 0.5.
        renderer.draw(fb, state, {600, {}, Topology::lines, {.line_width = 2.5f, .line_aa = true}}, shader);
        renderer.draw(fb, state, {n, strip, Topology::lines, {.line_width = 3, .line_aa = true}}, shader);
        constexpr std::size_t pixels = 301 * 203;
        std::vector<std::uint32_t> bytes(2 * pixels);  // colour, then the depth's bits
        std::memcpy(bytes.data(), fb.colour_data(), pixels * sizeof(Rgba8));
        std::memcpy(bytes.data() + pixels, fb.depth_data(), pixels * sizeof(float));
        return bytes;
    };
    const auto reference = render(1, 64);
    for (int threads : {2, 3})
        for (int tile : {8, 16, 64}) EXPECT_EQ(render(threads, tile), reference) << threads << " threads, tiles " << tile;
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        EXPECT_EQ(render(2, 32), reference) << isa;
    }
    select_isa("best");
}

}  // namespace
