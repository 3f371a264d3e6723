// Anti-aliasing by jittered frames: antialias_offsets' sample patterns, RenderSettings::pixel_offset
// moving the image, and `--aa N` of the command line (thumbs' default of 2, the averaging, the
// option's checks). Not the supersampling of --ssaa (scene_test, the goldens).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "facet/scene.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace fs = std::filesystem;

TEST(Antialias, SamplePatternsAreCentredDistinctAndInsideThePixel) {
    for (int n : {1, 2, 4, 8}) {
        const std::span<const Vec2> o = antialias_offsets(n);
        ASSERT_EQ(o.size(), static_cast<std::size_t>(n));
        float sx = 0, sy = 0;
        std::set<std::pair<float, float>> xs;
        std::set<float> columns, rows;
        for (const Vec2 v : o) {
            EXPECT_LT(std::fabs(v.x), 0.5f);
            EXPECT_LT(std::fabs(v.y), 0.5f);
            sx += v.x, sy += v.y;
            xs.insert({v.x, v.y});
            columns.insert(v.x), rows.insert(v.y);
        }
        EXPECT_EQ(sx, 0.0f) << n;  // the image does not move on average
        EXPECT_EQ(sy, 0.0f) << n;
        // Rotated grids: no two samples share a column or a row, so near-vertical and
        // near-horizontal edges get n levels each.
        EXPECT_EQ(columns.size(), static_cast<std::size_t>(n));
        EXPECT_EQ(rows.size(), static_cast<std::size_t>(n));
    }
    for (int n : {0, 3, 16, -1}) EXPECT_TRUE(antialias_offsets(n).empty()) << n;
}

// The centroid of the pixels a scene covers (mask shading: white on black).
Vec2 covered_centroid(const Image& image) {
    double x = 0, y = 0, w = 0;
    for (int j = 0; j < image.height; ++j)
        for (int i = 0; i < image.width; ++i) {
            const double c = image.at(i, j).r / 255.0;
            x += c * i, y += c * j, w += c;
        }
    return {static_cast<float>(x / w), static_cast<float>(y / w)};
}

// A sphere well inside the image (a third of its height across).
Image render_mask(Vec2 offset) {
    Scene scene;
    scene.objects.push_back({make_uv_sphere(1.0f, 48, 24), Mat4::identity(), Material{}});
    RenderSettings settings;
    settings.shading = Shading::mask;
    settings.background = {0, 0, 0, 1};
    settings.pixel_offset = offset;
    Renderer renderer({.threads = 2});
    Framebuffer target(160, 120);
    render_scene(renderer, target, scene, Camera::orbit({0, 0, 0}, 0, 0, 8), settings);
    return target.to_image();
}

TEST(Antialias, PixelOffsetMovesTheImageRightAndDown) {
    const Vec2 still = covered_centroid(render_mask({0, 0}));
    const Vec2 moved = covered_centroid(render_mask({3, -2}));
    EXPECT_NEAR(moved.x - still.x, 3.0f, 0.05f);
    EXPECT_NEAR(moved.y - still.y, -2.0f, 0.05f);
    const Vec2 nudged = covered_centroid(render_mask({0.25f, 0.25f}));
    EXPECT_NEAR(nudged.x - still.x, 0.25f, 0.1f);
    EXPECT_NEAR(nudged.y - still.y, 0.25f, 0.1f);
}

// A model's mask image from the command line with extra options.
facet_test::DecodedPng render_cli(const fs::path& dir, const std::string& name, std::vector<std::string> options) {
    const fs::path model = dir / "box.obj";
    if (!fs::exists(model)) facet_test::write_file(model, facet_test::k_box_obj);
    std::vector<std::string> args{"render", model.string(), "--size", "96x64", "--shading", "mask", "--background", "0,0,0",
                                  "--azimuth", "20", "--elevation", "15", "-o", (dir / name).string()};
    args.insert(args.end(), options.begin(), options.end());
    const facet_test::CliRun r = facet_test::run_facet(args);
    EXPECT_EQ(r.exit_code, 0) << r.all();
    return facet_test::decode_png(dir / name);
}

std::size_t partly_covered(const facet_test::DecodedPng& png) {
    return static_cast<std::size_t>(std::count_if(png.rgba.begin(), png.rgba.end(), [](Rgba8 c) { return c.r > 0 && c.r < 255; }));
}

TEST(Antialias, JitteredFramesAverageTheEdges) {
    const fs::path dir = facet_test::test_temp_dir("facet_aa");
    const facet_test::DecodedPng one = render_cli(dir, "aa1.png", {});
    const facet_test::DecodedPng two = render_cli(dir, "aa2.png", {"--aa", "2"});
    const facet_test::DecodedPng four = render_cli(dir, "aa4.png", {"--aa", "4"});
    ASSERT_TRUE(one.ok() && two.ok() && four.ok());
    // Without anti-aliasing a mask pixel is white or black; with n frames an edge pixel covered
    // by k of its n samples is 255 k / n, rounded.
    EXPECT_EQ(partly_covered(one), 0u);
    EXPECT_GT(partly_covered(two), 40u);
    for (const Rgba8 c : two.rgba) EXPECT_TRUE(c.r == 0 || c.r == 128 || c.r == 255) << int{c.r};
    std::set<int> levels;
    for (const Rgba8 c : four.rgba) levels.insert(c.r);
    EXPECT_EQ(levels, (std::set<int>{0, 64, 128, 191, 255}));
    // The same amount of white on average: anti-aliasing spreads the edges, it does not move them.
    auto white = [](const facet_test::DecodedPng& p) {
        double s = 0;
        for (const Rgba8 c : p.rgba) s += c.r / 255.0;
        return s;
    };
    EXPECT_NEAR(white(four), white(one), 0.02 * white(one));
    // Interior pixels keep their value.
    const std::uint32_t cx = one.width / 2, cy = one.height / 2;
    EXPECT_EQ(one.at(cx, cy).r, 255);
    EXPECT_EQ(four.at(cx, cy).r, 255);
}

TEST(Antialias, ThumbnailsDefaultToTwoFramesAndBadCountsAreUsageErrors) {
    const fs::path dir = facet_test::test_temp_dir("facet_aa");
    const std::string model = facet_test::write_file(dir / "box.obj", facet_test::k_box_obj);
    const facet_test::CliRun thumbs = facet_test::run_facet({"thumbs", model, "--print-config", "-o", (dir / "out").string()});
    EXPECT_NE(thumbs.out.find("aa = 2\n"), std::string::npos) << thumbs.all();
    const facet_test::CliRun render = facet_test::run_facet({"render", "--print-config"});
    EXPECT_NE(render.out.find("aa = 1\n"), std::string::npos) << render.all();
    for (const char* bad : {"3", "0", "16", "-2"}) {
        const facet_test::CliRun r = facet_test::run_facet({"render", "--aa", bad, "-o", "/nonexistent-facet-dir/x.png"});
        EXPECT_EQ(r.exit_code, 2) << r.all();
        EXPECT_NE(r.err.find("--aa must be 1, 2, 4 or 8"), std::string::npos) << r.all();
    }
}

}  // namespace
