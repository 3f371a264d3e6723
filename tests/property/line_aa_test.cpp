// Property: anti-aliased lines (PrimitiveStyle::line_aa) blend by the coverage rule of README.md
// ("Anti-aliased lines"), checked against a brute-force reference written from the rule alone: a
// segment's coverage of a pixel is min(1, the distance from the pixel centre to the edge of its band
// of half-width w/2 + 1/2, whose free ends reach 1/2 pixel past its end points). A strip's joins
// blend each pixel once and leave no gap; depth is tested against surfaces and never written; bad
// widths are refused as for aliased lines. The same bytes over threads, tile sizes and ISAs:
// points_lines_test.cpp's PointsAndLines.SameBytesOverThreadsTilesAndIsas draws them too.
//
// Ends are placed on the 1/256-pixel grid as in points_lines_test.cpp: on a 64x64 target with w = 1,
// clip x = X / 8192 - 1 projects to X / 256 pixels exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "facet/error.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

namespace {

using namespace facet;

constexpr int k_size = 64;

Vec4 clip_at(std::int32_t X, std::int32_t Y, float z = 0.5f) {
    return {static_cast<float>(X) / 8192.0f - 1.0f, 1.0f - static_cast<float>(Y) / 8192.0f, z, 1.0f};
}

// The rule's coverage of pixel (x, y) by the segment (ax, ay) -> (bx, by) (pixels) of width w, both
// ends free: the distance from the centre to the edge of the band |across| <= w/2 + 1/2,
// -1/2 <= along <= length + 1/2, at most 1, 0 outside.
double reference_coverage(double ax, double ay, double bx, double by, double w, int x, int y) {
    const double px = x + 0.5, py = y + 0.5;
    const double dx = bx - ax, dy = by - ay, length = std::sqrt(dx * dx + dy * dy);
    const double ux = dx / length, uy = dy / length;
    const double along = (px - ax) * ux + (py - ay) * uy, across = std::abs(-(px - ax) * uy + (py - ay) * ux);
    const double inside = std::min({w / 2 + 0.5 - across, along + 0.5, length + 0.5 - along});
    return std::clamp(inside, 0.0, 1.0);
}

DrawState blending_over_black() {
    DrawState state;
    state.depth_test = DepthTest::always;
    state.clear = ClearValues{{0, 0, 0, 1}, 1.0f};
    return state;
}

// White lines over black: each pixel's red is 255 times what the line blended there.
TEST(LineAa, CoverageFollowsTheRuleOnRandomSegments) {
    std::mt19937 rng(2601);
    std::uniform_int_distribution<std::int32_t> coordinate(-6 * 256, 70 * 256);
    std::uniform_real_distribution<float> width(0.3f, 9.0f);
    Renderer renderer({.threads = 2, .tile_size = 16});
    Framebuffer fb(k_size, k_size);
    int partial = 0, full = 0;
    for (int trial = 0; trial < 100; ++trial) {
        const std::int32_t X0 = coordinate(rng), Y0 = coordinate(rng);
        std::int32_t X1 = trial % 4 == 0 ? X0 + coordinate(rng) / 16 : coordinate(rng), Y1 = coordinate(rng);
        if (trial % 5 == 0) Y1 = Y0;  // horizontal: edges through pixel centres
        if (X1 == X0 && Y1 == Y0) ++X1;
        const std::vector<Vec4> pos = {clip_at(X0, Y0), clip_at(X1, Y1)};
        const auto placed = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                           [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
        const float w = trial % 7 == 0 ? static_cast<float>(1 + trial % 3) : width(rng);
        const DrawStats stats = renderer.draw(fb, blending_over_black(), {2, {}, Topology::lines, {.line_width = w, .line_aa = true}}, placed);
        EXPECT_EQ(stats.segments_in, 1u);
        for (int y = 0; y < k_size; ++y)
            for (int x = 0; x < k_size; ++x) {
                const double c = reference_coverage(X0 / 256.0, Y0 / 256.0, X1 / 256.0, Y1 / 256.0, w, x, y);
                partial += c > 0.05 && c < 0.95;
                full += c == 1;
                // Corners snapped to 1/256 pixel move the band's edges by less than 1/100 pixel.
                ASSERT_NEAR(fb.colour(x, y).r, 255 * c, 3.0)
                    << "pixel " << x << "," << y << " of " << X0 / 256.0 << "," << Y0 / 256.0 << " -> " << X1 / 256.0
                    << "," << Y1 / 256.0 << " width " << w;
                ASSERT_EQ(fb.depth(x, y), 1.0f) << "anti-aliased lines write no depth";
            }
    }
    EXPECT_GT(partial, 3000);
    EXPECT_GT(full, 3000);
}

// A zig-zag strip (each segment within 45 degrees of +x, so turns of at most 90 degrees, inside the
// mitre limit, and no segment reaches a non-neighbour): no pixel is blended twice, and every pixel
// centre within w/2 - 1/2 of the strip, away from its two free ends, is blended at full coverage.
TEST(LineAa, StripJoinsBlendEachPixelOnceWithoutGaps) {
    std::mt19937 rng(2602);
    std::uniform_real_distribution<double> angle(-0.78, 0.78), step(5.0, 10.0), start(20.0, 44.0);
    std::uniform_real_distribution<float> width(1.0f, 4.0f);
    int joined = 0;
    for (int trial = 0; trial < 40; ++trial) {
        std::vector<Vec4> pos;
        std::vector<double> px, py;
        double x = 4, y = start(rng);
        for (int k = 0; k < 9 && x < 60; ++k) {
            const auto X = static_cast<std::int32_t>(std::lround(x * 256)), Y = static_cast<std::int32_t>(std::lround(y * 256));
            pos.push_back(clip_at(X, Y));
            px.push_back(X / 256.0), py.push_back(Y / 256.0);
            const double a = angle(rng), s = step(rng);
            x += s * std::cos(a), y += s * std::sin(a);
        }
        std::vector<std::uint32_t> strip;
        for (std::uint32_t i = 0; i + 1 < pos.size(); ++i)
            if (px[i] != px[i + 1] || py[i] != py[i + 1]) strip.insert(strip.end(), {i, i + 1});
        const float w = width(rng);
        std::vector<std::atomic<int>> hits(k_size * k_size);  // fragments blended per pixel
        const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                           [&](const FragmentIn<0>& in) {
                                               const auto x = static_cast<std::size_t>(in.pos_screen.x);
                                               hits[static_cast<std::size_t>(in.pos_screen.y) * k_size + x]++;
                                               return Vec4{1, 1, 1, 1};
                                           });
        Renderer renderer({.threads = 2, .tile_size = 8});
        Framebuffer fb(k_size, k_size);
        renderer.draw(fb, blending_over_black(), {static_cast<std::uint32_t>(pos.size()), strip, Topology::lines, {.line_width = w, .line_aa = true}}, shader);
        for (int yy = 0; yy < k_size; ++yy)
            for (int xx = 0; xx < k_size; ++xx) {
                const int n = hits[static_cast<std::size_t>(yy) * k_size + xx].load();
                ASSERT_LE(n, 1) << "pixel " << xx << "," << yy << " blended twice, width " << w << ", trial " << trial;
                // Within w/2 - 1/2 of an interior stretch of the strip (the distance to the polyline, its
                // ends excluded by more than a pixel), coverage is 1 whatever segment owns the pixel.
                double nearest = 1e9;
                for (std::size_t s = 0; s + 1 < strip.size(); s += 2) {
                    const double ax = px[strip[s]], ay = py[strip[s]], bx = px[strip[s + 1]], by = py[strip[s + 1]];
                    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
                    const double t = std::clamp(((xx + 0.5 - ax) * dx + (yy + 0.5 - ay) * dy) / l2, 0.0, 1.0);
                    nearest = std::min(nearest, std::hypot(xx + 0.5 - ax - t * dx, yy + 0.5 - ay - t * dy));
                }
                const double from_ends = std::min(std::hypot(xx + 0.5 - px[strip.front()], yy + 0.5 - py[strip.front()]),
                                                  std::hypot(xx + 0.5 - px[strip.back()], yy + 0.5 - py[strip.back()]));
                if (nearest < w / 2 - 0.55 && from_ends > w / 2 + 1.5) {
                    ++joined;
                    ASSERT_EQ(n, 1) << "gap at pixel " << xx << "," << yy;
                    ASSERT_EQ(fb.colour(xx, yy).r, 255) << "pixel " << xx << "," << yy << " width " << w;
                }
            }
    }
    EXPECT_GT(joined, 2000);
}

// Behind a surface an anti-aliased line leaves it untouched; in front it blends over it; it never
// writes depth.
TEST(LineAa, IsDepthTestedAgainstSurfacesAndWritesNoDepth) {
    std::vector<Vec4> pos = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {1, 1, 0.5f, 1}, {-1, 1, 0.5f, 1}};
    for (auto [X, Y, z] : {std::tuple{4, 8, 0.4f}, {60, 8, 0.4f}, {4, 56, 0.6f}, {60, 56, 0.6f}})
        pos.push_back(clip_at(X * 256, Y * 256 + 128, z));
    // The quad (vertices 0-3) red, the lines green.
    const auto shader = make_shader<1>(
        [&](std::uint32_t i, Varyings<1>& out) {
            out[0] = i < 4 ? 0.0f : 1.0f;
            return pos[i];
        },
        [](const FragmentIn<1>& in) { return Vec4{1 - in.v[0], in.v[0], 0, 1}; });
    const std::uint32_t quad[] = {0, 1, 2, 0, 2, 3}, lines[] = {4, 5, 6, 7};
    const auto n = static_cast<std::uint32_t>(pos.size());
    Renderer renderer({.threads = 2, .tile_size = 16});
    Framebuffer surface(k_size, k_size), fb(k_size, k_size);
    DrawState state;
    state.clear = ClearValues{};
    renderer.draw(surface, state, {n, quad}, shader);
    renderer.draw(fb, state, {n, quad}, shader);
    state.clear.reset();
    const DrawStats stats = renderer.draw(fb, state, {n, lines, Topology::lines, {.line_width = 2, .line_aa = true}}, shader);
    EXPECT_EQ(stats.segments_in, 2u);
    EXPECT_EQ(std::memcmp(fb.depth_data(), surface.depth_data(), sizeof(float) * k_size * k_size), 0) << "no depth written";
    for (int x = 0; x < k_size; ++x) {
        for (int y = 48; y < k_size; ++y)  // the line behind
            ASSERT_EQ(fb.colour(x, y).r, surface.colour(x, y).r) << x << "," << y;
        ASSERT_EQ(fb.colour(x, 56).g, 0);
    }
    // In front, along y = 8.5: row 8 is green; rows 7 and 9, whose centres are 1 pixel off, are
    // covered by half (1.5 - 1) and mix green and red; row 6 is untouched.
    EXPECT_EQ(fb.colour(32, 8).g, 255);
    EXPECT_EQ(fb.colour(32, 8).r, 0);
    for (int y : {7, 9}) {
        EXPECT_NEAR(fb.colour(32, y).g, 127.5, 1) << y;
        EXPECT_NEAR(fb.colour(32, y).r, 127.5, 1) << y;
    }
    EXPECT_EQ(fb.colour(32, 6).r, 255);
    EXPECT_EQ(fb.colour(32, 6).g, 0);
}

// Bad widths are refused as for aliased lines; segments with a NaN end are dropped and counted.
TEST(LineAa, BadWidthsAreRefusedAndInvalidSegmentsCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<Vec4> pos = {clip_at(20 * 256, 20 * 256), {nan, 0, 0.5f, 1}, clip_at(40 * 256, 40 * 256)};
    const std::vector<std::uint32_t> lines = {0, 1, 0, 2, 9, 2};
    const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    Renderer renderer({.threads = 2});
    Framebuffer fb(k_size, k_size);
    const DrawStats stats = renderer.draw(fb, blending_over_black(), {3, lines, Topology::lines, {.line_width = 2, .line_aa = true}}, shader);
    EXPECT_EQ(stats.segments_in, 3u);
    EXPECT_EQ(stats.segments_invalid, 2u);
    EXPECT_EQ(fb.colour(30, 30).r, 255);
    for (float bad : {0.0f, -1.0f, nan, 257.0f, 1e30f, std::numeric_limits<float>::infinity()})
        EXPECT_THROW(renderer.draw(fb, blending_over_black(), {3, lines, Topology::lines, {.line_width = bad, .line_aa = true}}, shader),
                     FacetError)
            << bad;
}

}  // namespace

// render_scene draws an opaque object's anti-aliased lines after every opaque object's surfaces:
// a line listed before a surface behind it still shows over it (it writes no depth, so drawn
// first it would be painted over), and one behind a surface stays hidden.
TEST(LineAa, RenderSceneDrawsThemAfterTheOpaqueSurfaces) {
    const auto render = [](float line_z) {
        Mesh lines;  // red, along y = 0
        lines.positions = {{-2, 0, line_z}, {2, 0, line_z}};
        lines.colours = {{1, 0, 0, 1}, {1, 0, 0, 1}};
        lines.lines = {0, 1};
        Mesh quad;  // green, at z = 0
        quad.positions = {{-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0}};
        quad.colours.assign(4, Vec4{0, 1, 0, 1});
        quad.indices = {0, 1, 2, 0, 2, 3};
        Scene scene;
        scene.objects.push_back({std::move(lines), Mat4::identity(), Material{}});
        scene.objects.push_back({std::move(quad), Mat4::identity(), Material{}});
        RenderSettings settings;
        settings.shading = Shading::vertex_color;
        settings.primitives.line_width = 3;
        settings.primitives.line_aa = true;
        Renderer renderer({.threads = 2});
        Framebuffer target(64, 48);
        render_scene(renderer, target, scene, Camera::orbit({0, 0, 0}, 0, 0, 8), settings);
        return target.to_image();
    };
    const Image in_front = render(0.5f), behind = render(-0.5f);
    EXPECT_EQ(in_front.at(32, 24).r, 255);
    EXPECT_EQ(in_front.at(32, 24).g, 0);
    EXPECT_EQ(in_front.at(32, 10).g, 255);
    for (int y = 10; y < 38; ++y) EXPECT_EQ(behind.at(32, y).r, 0) << y;  // within the quad
}
