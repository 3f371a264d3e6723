// Textures: mip chain sizes and filtering (even and odd sides), sampling (nearest, bilinear,
// trilinear), wrap modes, level-of-detail selection, non-finite input, and decoding with limits.
// Expected values are derived by hand in the comments next to them.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <vector>

#include "facet/io.hpp"
#include "facet/math/portable_pow.hpp"
#include "facet/texture.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

Image make_image(int w, int h, const std::function<Rgba8(int, int)>& texel) {
    Image img{w, h, std::vector<Rgba8>(static_cast<std::size_t>(w) * h)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = texel(x, y);
    return img;
}

Rgba8 grey(int v) { return {std::uint8_t(v), std::uint8_t(v), std::uint8_t(v), 255}; }

// A 4x4 texture whose red channel numbers the columns and green the rows: r = 0, 60, 120, 240
// (not evenly spaced, so averages are distinguishable), g = 10, 50, 90, 200.
constexpr int k_col[4] = {0, 60, 120, 240};
constexpr int k_row[4] = {10, 50, 90, 200};
Texture grid4() {
    return Texture(make_image(4, 4, [](int x, int y) { return Rgba8{std::uint8_t(k_col[x]), std::uint8_t(k_row[y]), 7, 255}; }));
}

void expect_near(Vec4 got, Vec4 want, float tol = 1e-6f) {
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], tol) << "channel " << i;
}

fs::path temp_dir(const char* name) {
    fs::path d = fs::temp_directory_path() / ("facet_texture_test_" + std::string(name));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write_bytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

bool mentions(const Error& e, const std::string& what) { return e.message.find(what) != std::string::npos; }

const Sampler k_nearest{Wrap::repeat, Wrap::repeat, Filter::nearest};
const Sampler k_bilinear{Wrap::repeat, Wrap::repeat, Filter::bilinear};
const Sampler k_trilinear{Wrap::repeat, Wrap::repeat, Filter::trilinear};

// ---- mip chain -----------------------------------------------------------------------------------

TEST(TextureMips, SquarePowerOfTwoHalvesDownToOneTexel) {
    const Texture t(make_image(256, 256, [](int, int) { return grey(9); }));
    ASSERT_EQ(t.level_count(), 9);  // 256, 128, 64, 32, 16, 8, 4, 2, 1
    for (int i = 0; i < 9; ++i) {
        EXPECT_EQ(t.level(i).width, 256 >> i);
        EXPECT_EQ(t.level(i).height, 256 >> i);
        EXPECT_EQ(t.level(i).pixels.size(), std::size_t(256 >> i) * std::size_t(256 >> i));
    }
}

TEST(TextureMips, OddSidesRoundDownAndStopAtOne) {
    const Texture t(make_image(300, 7, [](int, int) { return grey(9); }));
    // Width 300 150 75 37 18 9 4 2 1; height 7 3 1 and then stays 1.
    const int widths[] = {300, 150, 75, 37, 18, 9, 4, 2, 1};
    const int heights[] = {7, 3, 1, 1, 1, 1, 1, 1, 1};
    ASSERT_EQ(t.level_count(), 9);
    for (int i = 0; i < 9; ++i) {
        EXPECT_EQ(t.level(i).width, widths[i]) << "level " << i;
        EXPECT_EQ(t.level(i).height, heights[i]) << "level " << i;
    }
    // A constant image stays constant through every filter.
    for (int i = 0; i < 9; ++i)
        for (Rgba8 p : t.level(i).pixels) EXPECT_EQ(p, grey(9));
}

TEST(TextureMips, OneTexelHasOneLevel) {
    const Texture t(make_image(1, 1, [](int, int) { return Rgba8{1, 2, 3, 4}; }));
    EXPECT_EQ(t.level_count(), 1);
    EXPECT_EQ(t.width(), 1);
    EXPECT_EQ(t.height(), 1);
}

TEST(TextureMips, TwoByTwoAveragesAndRoundsHalvesUp) {
    const Rgba8 texels[4] = {{10, 0, 0, 255}, {20, 0, 0, 255}, {30, 1, 0, 255}, {41, 1, 1, 253}};
    const Texture t(make_image(2, 2, [&](int x, int y) { return texels[y * 2 + x]; }));
    ASSERT_EQ(t.level_count(), 2);
    // r: 101 / 4 = 25.25 -> 25; g: 2 / 4 = 0.5 -> 1; b: 1 / 4 = 0.25 -> 0; a: 1018 / 4 = 254.5 -> 255.
    EXPECT_EQ(t.level(1).at(0, 0), (Rgba8{25, 1, 0, 255}));
}

TEST(TextureMips, OddRowUsesAreaWeightsSoNoTexelIsDropped) {
    // 3 -> 1: weights (1, 1, 1) / 3: (30 + 60 + 255) / 3 = 115.
    const int three[] = {30, 60, 255};
    const Texture t3(make_image(3, 1, [&](int x, int) { return grey(three[x]); }));
    ASSERT_EQ(t3.level_count(), 2);
    EXPECT_EQ(t3.level(1).at(0, 0), grey(115));

    // 5 -> 2: output j covers 2.5 texels, weights (2, 2, 1) / 5 and (1, 2, 2) / 5:
    // (20 + 40 + 30) / 5 = 18 and (30 + 80 + 100) / 5 = 42. The mean (30) is kept.
    const int five[] = {10, 20, 30, 40, 50};
    const Texture t5(make_image(5, 1, [&](int x, int) { return grey(five[x]); }));
    EXPECT_EQ(t5.level(1).width, 2);
    EXPECT_EQ(t5.level(1).at(0, 0), grey(18));
    EXPECT_EQ(t5.level(1).at(1, 0), grey(42));

    // 3x3 -> 1x1: every texel weighs 1/9; values 0, 10, ..., 80 average 40.
    const Texture t33(make_image(3, 3, [](int x, int y) { return grey(10 * (y * 3 + x)); }));
    EXPECT_EQ(t33.level(1).at(0, 0), grey(40));

    // Rounding of thirds: 1/3 -> 0, 2/3 -> 1.
    EXPECT_EQ(Texture(make_image(3, 1, [](int x, int) { return grey(x == 2); })).level(1).at(0, 0), grey(0));
    EXPECT_EQ(Texture(make_image(3, 1, [](int x, int) { return grey(x >= 1); })).level(1).at(0, 0), grey(1));
}

TEST(TextureMips, CheckerboardConvergesToGrey) {
    auto checker = [](int x, int y) { return grey((x + y) % 2 ? 255 : 0); };
    // Even: every 2x2 block holds two 0s and two 255s: 510 / 4 = 127.5 -> 128, then 128 forever.
    const Texture even(make_image(8, 8, checker));
    for (int i = 1; i < even.level_count(); ++i)
        for (Rgba8 p : even.level(i).pixels) EXPECT_EQ(p, grey(128)) << "level " << i;
    // Odd: the area filter keeps the mean. White where x + y is odd: 40 of the 81 texels (the
    // corners are black), 255 * 40 / 81 = 125.93, up to half a step of rounding at each of 3 levels.
    const Texture odd(make_image(9, 9, checker));
    ASSERT_EQ(odd.level_count(), 4);  // 9, 4, 2, 1
    const Rgba8 last = odd.level(3).at(0, 0);
    EXPECT_NEAR(last.r, 255.0 * 40 / 81, 1.5);
    EXPECT_EQ(last.a, 255);
}

TEST(TextureMips, ConstructorRejectsEmptyAndMismatchedImages) {
    try {
        Texture t{Image{}};
        FAIL() << "an empty image was accepted";
    } catch (const FacetError& e) {
        EXPECT_EQ(e.error().code, ErrorCode::invalid_argument);
    }
    Image short_by_one{4, 4, std::vector<Rgba8>(15)};
    EXPECT_THROW(Texture{short_by_one}, FacetError);
    Image negative{-2, 3, {}};
    EXPECT_THROW(Texture{negative}, FacetError);
}

TEST(TextureMips, TransparencyMeansAnyAlphaBelowOpaque) {
    EXPECT_FALSE(Texture(make_image(5, 3, [](int, int) { return grey(0); })).has_transparency());
    EXPECT_TRUE(Texture(make_image(5, 3, [](int x, int y) {
                    return x == 4 && y == 2 ? Rgba8{0, 0, 0, 254} : grey(0);
                })).has_transparency());
}

// The rectangle of texels whose alpha is not 0: every such texel inside, the rest of the rows and
// columns outside it with alpha 0; empty for a fully transparent image, the whole for an opaque one.
TEST(TextureMips, AlphaBoundsHoldEveryTexelWithAlpha) {
    auto bounds = [](int w, int h, const std::function<bool(int, int)>& has_alpha) {
        const TexelRect b = Texture(make_image(w, h, [&](int x, int y) {
                                return Rgba8{9, 9, 9, static_cast<std::uint8_t>(has_alpha(x, y) ? 1 + x : 0)};
                            })).alpha_bounds();
        return std::vector<int>{b.x0, b.y0, b.x1, b.y1};
    };
    EXPECT_EQ(bounds(7, 5, [](int, int) { return true; }), (std::vector<int>{0, 0, 7, 5}));
    EXPECT_EQ(bounds(7, 5, [](int, int) { return false; }), (std::vector<int>{0, 0, 0, 0}));
    EXPECT_EQ(bounds(7, 5, [](int x, int y) { return x == 3 && y == 1; }), (std::vector<int>{3, 1, 4, 2}));
    EXPECT_EQ(bounds(7, 5, [](int x, int y) { return (x == 1 && y == 4) || (x == 5 && y == 2); }), (std::vector<int>{1, 2, 6, 5}));
}

// ---- sampling ------------------------------------------------------------------------------------

TEST(TextureSample, TexelCentresReturnTheExactTexel) {
    const Texture t = grid4();
    for (const Sampler& s : {k_nearest, k_bilinear, k_trilinear})
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const Vec2 uv{(x + 0.5f) / 4, (y + 0.5f) / 4};
                const Vec4 want = to_vec4(t.level(0).at(x, y));
                EXPECT_EQ(t.sample_lod(uv, 0.0f, s), want) << x << "," << y;
                EXPECT_EQ(t.sample(uv, {0.25f / 4, 0}, {0, 0.25f / 4}, s), want) << x << "," << y;
            }
}

TEST(TextureSample, VTopRowIsTheFirstRowOfTheImage) {
    const Texture t = grid4();
    EXPECT_NEAR(t.sample_lod({0.125f, 0.01f}, 0, k_nearest).y, 10 / 255.0f, 1e-6f);
    EXPECT_NEAR(t.sample_lod({0.125f, 0.99f}, 0, k_nearest).y, 200 / 255.0f, 1e-6f);
}

TEST(TextureSample, BilinearHalfwayIsTheAverage) {
    const Texture t = grid4();
    // u = 0.25 is halfway between the centres of columns 0 and 1: r = (0 + 60) / 2 = 30.
    expect_near(t.sample_lod({0.25f, 0.125f}, 0, k_bilinear), Vec4{30, 10, 7, 255} / 255.0f);
    // Between four texels: r = (120 + 240) / 2 = 180, g = (50 + 90) / 2 = 70.
    expect_near(t.sample_lod({0.75f, 0.5f}, 0, k_bilinear), Vec4{180, 70, 7, 255} / 255.0f);
    // A quarter of the way from column 1 to column 2: 60 + 0.25 * 60 = 75.
    expect_near(t.sample_lod({0.4375f, 0.125f}, 0, k_bilinear), Vec4{75, 10, 7, 255} / 255.0f);
}

TEST(TextureSample, NearestPicksTheTexelContainingUv) {
    const Texture t = grid4();
    EXPECT_NEAR(t.sample_lod({0.49f, 0.1f}, 0, k_nearest).x, 60 / 255.0f, 1e-6f);   // column 1
    EXPECT_NEAR(t.sample_lod({0.51f, 0.1f}, 0, k_nearest).x, 120 / 255.0f, 1e-6f);  // column 2
    // u = 1 wraps to column 0 under repeat, stays on column 3 under clamp and mirror.
    EXPECT_NEAR(t.sample_lod({1.0f, 0.1f}, 0, k_nearest).x, 0.0f, 1e-6f);
    EXPECT_NEAR(t.sample_lod({1.0f, 0.1f}, 0, {Wrap::clamp, Wrap::clamp, Filter::nearest}).x, 240 / 255.0f, 1e-6f);
    EXPECT_NEAR(t.sample_lod({1.0f, 0.1f}, 0, {Wrap::mirror, Wrap::mirror, Filter::nearest}).x, 240 / 255.0f, 1e-6f);
    // Just below 0 is the last column under repeat.
    EXPECT_NEAR(t.sample_lod({-1e-7f, 0.1f}, 0, k_nearest).x, 240 / 255.0f, 1e-6f);
}

// Red channel at (u, v = row 0 centre) under a wrap mode, bilinear.
float red_at(const Texture& t, float u, Wrap wrap) {
    return t.sample_lod({u, 0.125f}, 0, {wrap, Wrap::clamp, Filter::bilinear}).x * 255.0f;
}
// Green channel at (u = column 0 centre, v) under a wrap mode for v.
float green_at(const Texture& t, float v, Wrap wrap) {
    return t.sample_lod({0.125f, v}, 0, {Wrap::clamp, wrap, Filter::bilinear}).y * 255.0f;
}

TEST(TextureSample, WrapModesOutsideTheUnitSquare) {
    const Texture t = grid4();
    // Columns r = 0, 60, 120, 240 at centres u = 0.125, 0.375, 0.625, 0.875.
    // u = -0.25: repeat -> 0.75, between columns 2 and 3: 180. clamp -> column 0: 0.
    //            mirror -> 0.25, between columns 0 and 1: 30.
    EXPECT_NEAR(red_at(t, -0.25f, Wrap::repeat), 180.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, -0.25f, Wrap::clamp), 0.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, -0.25f, Wrap::mirror), 30.0f, 1e-3f);
    // u = 1.25: repeat -> 0.25: 30. clamp -> column 3: 240. mirror -> 2 - 1.25 = 0.75: 180.
    EXPECT_NEAR(red_at(t, 1.25f, Wrap::repeat), 30.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 1.25f, Wrap::clamp), 240.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 1.25f, Wrap::mirror), 180.0f, 1e-3f);
    // u = -0.375: repeat -> 0.625, column 2: 120. clamp: 0. mirror -> 0.375, column 1: 60.
    EXPECT_NEAR(red_at(t, -0.375f, Wrap::repeat), 120.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, -0.375f, Wrap::clamp), 0.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, -0.375f, Wrap::mirror), 60.0f, 1e-3f);
    // u = 1.375: repeat -> 0.375: 60. clamp: 240. mirror -> 0.625: 120.
    EXPECT_NEAR(red_at(t, 1.375f, Wrap::repeat), 60.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 1.375f, Wrap::clamp), 240.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 1.375f, Wrap::mirror), 120.0f, 1e-3f);
    // u = -2.875: repeat -> 0.125: 0. mirror: period 2, -2.875 + 4 = 1.125 -> 0.875, column 3: 240.
    EXPECT_NEAR(red_at(t, -2.875f, Wrap::repeat), 0.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, -2.875f, Wrap::mirror), 240.0f, 1e-3f);
    // At u = 0 repeat blends the last and first columns: (240 + 0) / 2; clamp and mirror stay on 0.
    EXPECT_NEAR(red_at(t, 0.0f, Wrap::repeat), 120.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 0.0f, Wrap::clamp), 0.0f, 1e-3f);
    EXPECT_NEAR(red_at(t, 0.0f, Wrap::mirror), 0.0f, 1e-3f);

    // The same along v, rows g = 10, 50, 90, 200: v = -0.25 repeat (90 + 200) / 2 = 145, clamp 10,
    // mirror (10 + 50) / 2 = 30; v = 1.375 repeat row 1: 50, clamp 200, mirror row 2: 90.
    EXPECT_NEAR(green_at(t, -0.25f, Wrap::repeat), 145.0f, 1e-3f);
    EXPECT_NEAR(green_at(t, -0.25f, Wrap::clamp), 10.0f, 1e-3f);
    EXPECT_NEAR(green_at(t, -0.25f, Wrap::mirror), 30.0f, 1e-3f);
    EXPECT_NEAR(green_at(t, 1.375f, Wrap::repeat), 50.0f, 1e-3f);
    EXPECT_NEAR(green_at(t, 1.375f, Wrap::clamp), 200.0f, 1e-3f);
    EXPECT_NEAR(green_at(t, 1.375f, Wrap::mirror), 90.0f, 1e-3f);
}

TEST(TextureSample, WrapModesApplyPerAxis) {
    const Texture t = grid4();
    // u repeats (-0.375 -> column 2: r 120), v clamps (-0.375 -> row 0: g 10).
    const Vec4 c = t.sample_lod({-0.375f, -0.375f}, 0, {Wrap::repeat, Wrap::clamp, Filter::bilinear});
    expect_near(c, Vec4{120, 10, 7, 255} / 255.0f);
}

TEST(TextureSample, TrilinearBlendsNeighbouringLevels) {
    // 2x2: level 1 is the average, r = (0 + 100 + 200 + 40) / 4 = 85.
    const int r[4] = {0, 100, 200, 40};
    const Texture t(make_image(2, 2, [&](int x, int y) { return Rgba8{std::uint8_t(r[y * 2 + x]), 0, 0, 255}; }));
    ASSERT_EQ(t.level(1).at(0, 0).r, 85);
    const Vec2 uv{0.25f, 0.25f};  // centre of texel (0, 0)
    // lod 0.5: (0 + 85) / 2 = 42.5; lod 0.25: 0.75 * 0 + 0.25 * 85 = 21.25.
    EXPECT_NEAR(t.sample_lod(uv, 0.5f, k_trilinear).x * 255, 42.5f, 1e-4f);
    EXPECT_NEAR(t.sample_lod(uv, 0.25f, k_trilinear).x * 255, 21.25f, 1e-4f);
    // lod is clamped to [0, 1]: 7 reads level 1, -3 level 0.
    EXPECT_NEAR(t.sample_lod(uv, 7.0f, k_trilinear).x * 255, 85.0f, 1e-4f);
    EXPECT_NEAR(t.sample_lod(uv, -3.0f, k_trilinear).x * 255, 0.0f, 1e-4f);
    // nearest and bilinear ignore lod: level 0.
    EXPECT_NEAR(t.sample_lod(uv, 1.0f, k_bilinear).x * 255, 0.0f, 1e-4f);
    EXPECT_NEAR(t.sample_lod(uv, 1.0f, k_nearest).x * 255, 0.0f, 1e-4f);
}

TEST(TextureSample, LodIsLog2OfTheLargerFootprintInTexels) {
    const Texture t(make_image(16, 4, [](int, int) { return grey(0); }));
    EXPECT_FLOAT_EQ(t.lod({1.0f / 16, 0}, {0, 1.0f / 4}), 0.0f);  // one texel per pixel both ways
    EXPECT_FLOAT_EQ(t.lod({4.0f / 16, 0}, {0, 1.0f / 4}), 2.0f);  // 4 texels per pixel along x
    EXPECT_FLOAT_EQ(t.lod({1.0f / 16, 0}, {0, 2.0f / 4}), 1.0f);  // v is measured in the 4 rows
    // A diagonal step of (3, 4) texels is 5 long.
    EXPECT_NEAR(t.lod({3.0f / 16, 4.0f / 4}, {0, 0}), std::log2(5.0f), 1e-6f);
    EXPECT_LT(t.lod({0.5f / 16, 0}, {0, 0.5f / 4}), 0.0f);  // magnified: below 0, clamped when sampling
    EXPECT_EQ(t.lod({0, 0}, {0, 0}), 0.0f);
    EXPECT_EQ(t.lod({k_nan, 0}, {0, 1}), 0.0f);
    EXPECT_EQ(t.lod({0, 1}, {0, k_nan}), 0.0f);
}

// The level of detail has the same bits on every machine: it is portable_log2 of the footprint, not
// the C library's log2f, which differs between CPUs and library versions. The footprints tried
// include ones where this machine's log2f gives other bits (counted, so the test keeps telling).
TEST(TextureSample, LodIsThePortableLog2OfTheFootprint) {
    const Texture t(make_image(1, 1, [](int, int) { return grey(0); }));  // rho = |duv| in texels
    int libm_differs = 0;
    for (int i = 0; i < 4096; ++i) {
        const float r = std::ldexp(1.0f + static_cast<float>(i) / 4096, i % 24 - 12);
        const Vec2 dx{r, 0}, dy{0, r / 2};
        const float rho = length(dx);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(t.lod(dx, dy)), std::bit_cast<std::uint32_t>(portable_log2(rho))) << r;
        libm_differs += std::log2(rho) != portable_log2(rho);
    }
    EXPECT_GT(libm_differs, 0) << "no footprint here tells portable_log2 from this machine's log2f";
    EXPECT_EQ(t.lod({k_inf, 0}, {0, 0}), k_inf);
}

TEST(TextureSample, DerivativesChooseTheLevel) {
    // 16 columns, stripes 4 wide: white at x = 4..7 and 12..15. Level 1 (8 wide): white columns
    // 2, 3, 6, 7; level 2 (4 wide): white 1, 3; level 3 (2 wide): 128 everywhere.
    const Texture t(make_image(16, 16, [](int x, int) { return grey((x / 4) % 2 ? 255 : 0); }));
    // At u = 5/16: level 0 x = 4.5 (columns 4, 5: 255); level 1 x = 2 (column 2: 255);
    // level 2 x = 0.75 (0.25 * 0 + 0.75 * 255 = 191.25); level 3: 128.
    const Vec2 uv{5.0f / 16, 0.5f};
    auto red = [&](float texels_per_pixel) {
        return t.sample(uv, {texels_per_pixel / 16, 0}, {0, texels_per_pixel / 16}, k_trilinear).x * 255;
    };
    EXPECT_NEAR(red(1), 255.0f, 1e-3f);     // lod 0
    EXPECT_NEAR(red(4), 191.25f, 1e-3f);    // lod 2
    EXPECT_NEAR(red(8), 128.0f, 1e-3f);     // lod 3
    EXPECT_NEAR(red(0.25f), 255.0f, 1e-3f); // magnified: lod 0
    // The larger of the two directions wins: 4 texels along y alone is lod 2 too.
    EXPECT_NEAR(t.sample(uv, {1.0f / 16, 0}, {0, 4.0f / 16}, k_trilinear).x * 255, 191.25f, 1e-3f);
    // Bilinear ignores the derivatives: level 0.
    EXPECT_NEAR(t.sample(uv, {4.0f / 16, 0}, {0, 4.0f / 16}, k_bilinear).x * 255, 255.0f, 1e-3f);
}

TEST(TextureSample, NonFiniteInputGivesAFiniteColour) {
    const Texture t = grid4();
    const float bad[] = {k_nan, k_inf, -k_inf, 1e30f, -1e30f, 3e9f};
    for (Wrap w : {Wrap::repeat, Wrap::clamp, Wrap::mirror})
        for (Filter f : {Filter::nearest, Filter::bilinear, Filter::trilinear}) {
            const Sampler s{w, w, f};
            for (float b : bad) {
                const Vec4 outs[] = {
                    t.sample_lod({b, 0.3f}, 0, s), t.sample_lod({0.3f, b}, 0, s), t.sample_lod({b, b}, b, s),
                    t.sample({0.3f, 0.3f}, {b, 0}, {0, b}, s), t.sample({b, b}, {b, b}, {b, b}, s)};
                for (Vec4 c : outs)
                    for (std::size_t i = 0; i < 4; ++i) {
                        EXPECT_TRUE(std::isfinite(c[i])) << "input " << b;
                        EXPECT_GE(c[i], 0.0f);
                        EXPECT_LE(c[i], 1.0f);
                    }
            }
        }
    // A NaN coordinate reads as 0: under clamp, column 0.
    EXPECT_NEAR(t.sample_lod({k_nan, 0.125f}, 0, {Wrap::clamp, Wrap::clamp, Filter::bilinear}).x, 0.0f, 1e-6f);
}

// ---- decoding ------------------------------------------------------------------------------------

// Only a PNG signature and an IHDR chunk (CRCs computed with Python's zlib.crc32 when the test was
// written). 100000 x 100000 RGBA: stb_image refuses it as "too large" before facet's own check.
const std::vector<unsigned char> k_png_100000 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
    0x01, 0x86, 0xa0, 0x00, 0x01, 0x86, 0xa0, 0x08, 0x06, 0x00, 0x00, 0x00, 0xa8, 0x52, 0x0b, 0xc8};
// 16000 x 16000 RGB: stb_image's header check accepts it; 256M pixels exceed max_pixels (64M).
const std::vector<unsigned char> k_png_16000 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
    0x00, 0x3e, 0x80, 0x00, 0x00, 0x3e, 0x80, 0x08, 0x02, 0x00, 0x00, 0x00, 0xce, 0x1c, 0x48, 0x89};

// A baseline greyscale JPEG, 8 wide and 16 tall (two 8x8 blocks, top then bottom), assembled by
// hand. Quantisation 8 for every coefficient, so a DC coefficient d gives pixels 128 + d.
// Top block: DC 72 -> 200. Bottom block: DC -72 -> 56, coded as the difference -144.
// DC Huffman table: category 7 -> "0", category 8 -> "10"; AC table: end-of-block -> "0".
// Bits: 0 1001000 0 | 10 01101111 0 | 1111 (padding) = 0x48 0x4d 0xef.
std::vector<unsigned char> two_block_jpeg(int declared_width = 8, int declared_height = 16) {
    std::vector<unsigned char> j;
    j.reserve(160);  // (also keeps GCC 12's -Warray-bounds false positive on insert quiet)
    const unsigned char head[] = {0xff, 0xd8,                     // SOI
                                  0xff, 0xdb, 0x00, 0x43, 0x00};  // DQT, 8-bit table 0
    j.insert(j.end(), std::begin(head), std::end(head));
    j.insert(j.end(), 64, 0x08);
    const unsigned char sof[] = {0xff, 0xc0, 0x00, 0x0b, 0x08,  // SOF0, 8-bit
                                 std::uint8_t(declared_height >> 8), std::uint8_t(declared_height),
                                 std::uint8_t(declared_width >> 8), std::uint8_t(declared_width),
                                 0x01, 0x01, 0x11, 0x00};       // one component, 1x1, table 0
    j.insert(j.end(), std::begin(sof), std::end(sof));
    const unsigned char rest[] = {
        0xff, 0xc4, 0x00, 0x15, 0x00, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x07, 0x08,  // DHT DC 0
        0xff, 0xc4, 0x00, 0x14, 0x10, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x00,        // DHT AC 0
        0xff, 0xda, 0x00, 0x08, 0x01, 0x01, 0x00, 0x00, 0x3f, 0x00,                                // SOS
        0x48, 0x4d, 0xef,                                                                          // scan
        0xff, 0xd9};                                                                               // EOI
    j.insert(j.end(), std::begin(rest), std::end(rest));
    return j;
}

Image rgba_gradient(int w, int h) {
    return make_image(w, h, [](int x, int y) {
        return Rgba8{std::uint8_t(x * 7), std::uint8_t(y * 13), std::uint8_t(x ^ y), std::uint8_t(255 - x)};
    });
}

TEST(TextureLoad, PngRoundTripsExactly) {
    const fs::path dir = temp_dir("png");
    const std::string path = (dir / "gradient.png").string();
    const Image img = rgba_gradient(37, 23);
    ASSERT_TRUE(write_png(path, img).ok());
    auto t = Texture::load(path);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ((*t)->width(), 37);
    EXPECT_EQ((*t)->height(), 23);
    EXPECT_TRUE((*t)->level(0).pixels == img.pixels);  // also: row 0 of the file is row 0, no flip
    EXPECT_TRUE((*t)->has_transparency());
    EXPECT_EQ((*t)->level_count(), 6);  // 37x23, 18x11, 9x5, 4x2, 2x1, 1x1
}

TEST(TextureLoad, DecodesFromMemory) {
    const fs::path dir = temp_dir("memory");
    const std::string path = (dir / "g.png").string();
    const Image img = rgba_gradient(5, 9);
    ASSERT_TRUE(write_png(path, img).ok());
    std::ifstream in(path, std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto t = Texture::decode(bytes.data(), bytes.size(), "model.glb#image0");
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_TRUE((*t)->level(0).pixels == img.pixels);
}

TEST(TextureLoad, JpegDecodesToRgbaTopRowFirst) {
    const std::vector<unsigned char> jpeg = two_block_jpeg();
    auto t = Texture::decode(jpeg.data(), jpeg.size(), "two_blocks.jpg");
    ASSERT_TRUE(t.ok()) << t.error().message;
    ASSERT_EQ((*t)->width(), 8);
    ASSERT_EQ((*t)->height(), 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 8; ++x) {
            const Rgba8 p = (*t)->level(0).at(x, y);
            const int want = y < 8 ? 200 : 56;  // the IDCT's fixed point may round by one
            EXPECT_NEAR(p.r, want, 1) << x << "," << y;
            EXPECT_EQ(p.g, p.r);
            EXPECT_EQ(p.b, p.r);
            EXPECT_EQ(p.a, 255);  // grey decodes to opaque RGBA
        }
    EXPECT_FALSE((*t)->has_transparency());
}

TEST(TextureLoad, MissingFileIsAnIoErrorNamingThePath) {
    const std::string path = "/nonexistent-dir-for-facet/texture.png";
    auto t = Texture::load(path);
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().code, ErrorCode::io);
    EXPECT_TRUE(mentions(t.error(), path)) << t.error().message;
    EXPECT_TRUE(mentions(t.error(), "No such file")) << t.error().message;
}

TEST(TextureLoad, DirectoryIsAnIoError) {
    const fs::path dir = temp_dir("directory");
    auto t = Texture::load(dir.string());
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().code, ErrorCode::io);
    EXPECT_TRUE(mentions(t.error(), dir.string())) << t.error().message;
}

TEST(TextureLoad, GarbageIsABadFormatNamingTheFile) {
    const fs::path dir = temp_dir("garbage");
    const fs::path path = dir / "notes.png";
    const std::string text = "this is not an image, just some words in a file";
    write_bytes(path, std::vector<unsigned char>(text.begin(), text.end()));
    auto t = Texture::load(path.string());
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().code, ErrorCode::bad_format);
    EXPECT_TRUE(mentions(t.error(), path.string())) << t.error().message;

    auto m = Texture::decode(text.data(), text.size(), "scene.glb image 3");
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().code, ErrorCode::bad_format);
    EXPECT_TRUE(mentions(m.error(), "scene.glb image 3")) << m.error().message;

    auto empty = Texture::decode(text.data(), 0, "empty");
    ASSERT_FALSE(empty.ok());
    EXPECT_EQ(empty.error().code, ErrorCode::bad_format);

    // A PNG cut off after its header is corrupt, not too large.
    std::vector<unsigned char> truncated = k_png_16000;
    truncated[18] = 0, truncated[19] = 16, truncated[22] = 0, truncated[23] = 16;  // 16x16, no pixel data
    auto cut = Texture::decode(truncated.data(), truncated.size(), "cut.png");
    ASSERT_FALSE(cut.ok());
    EXPECT_EQ(cut.error().code, ErrorCode::bad_format);
}

// JPEG goes through libjpeg-turbo, whose decoder finishes a cut file in grey with a warning: every
// cut of a JPEG is an error naming the file, not an image (the whole file decodes).
TEST(TextureLoad, TruncatedJpegIsAnError) {
    const std::vector<unsigned char> jpeg = two_block_jpeg();
    ASSERT_TRUE(Texture::decode(jpeg.data(), jpeg.size(), "whole.jpg").ok());
    for (std::size_t size = 1; size < jpeg.size(); ++size) {
        auto cut = Texture::decode(jpeg.data(), size, "cut.jpg");
        ASSERT_FALSE(cut.ok()) << size << " of " << jpeg.size() << " bytes";
        EXPECT_EQ(cut.error().code, ErrorCode::bad_format) << size;
        EXPECT_TRUE(mentions(cut.error(), "cut.jpg")) << cut.error().message;
    }
}

TEST(TextureLoad, HugeHeadersExceedTheLimitsBeforeDecoding) {
    const fs::path dir = temp_dir("huge");
    const fs::path path = dir / "huge.png";
    write_bytes(path, k_png_100000);
    auto t = Texture::load(path.string());
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(t.error(), path.string())) << t.error().message;
    EXPECT_TRUE(mentions(t.error(), "100000x100000")) << t.error().message;

    // Sides within 16384 but 256M pixels: over max_pixels.
    auto p = Texture::decode(k_png_16000.data(), k_png_16000.size(), "wide.png");
    ASSERT_FALSE(p.ok());
    EXPECT_EQ(p.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(p.error(), "16000x16000")) << p.error().message;

    // A JPEG header claiming 60000 x 60000 (no pixels follow).
    const std::vector<unsigned char> jpeg = two_block_jpeg(60000, 60000);
    auto j = Texture::decode(jpeg.data(), jpeg.size(), "big.jpg");
    ASSERT_FALSE(j.ok());
    EXPECT_EQ(j.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(j.error(), "60000x60000")) << j.error().message;
}

TEST(TextureLoad, ConfiguredLimitsAreRespected) {
    const fs::path dir = temp_dir("limits");
    const std::string path = (dir / "64.png").string();
    ASSERT_TRUE(write_png(path, rgba_gradient(64, 64)).ok());

    auto side = Texture::load(path, TextureLimits{32});
    ASSERT_FALSE(side.ok());
    EXPECT_EQ(side.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(side.error(), "64x64")) << side.error().message;
    EXPECT_TRUE(mentions(side.error(), path)) << side.error().message;

    auto pixels = Texture::load(path, TextureLimits{64, 4095});
    ASSERT_FALSE(pixels.ok());
    EXPECT_EQ(pixels.error().code, ErrorCode::limit_exceeded);

    auto exact = Texture::load(path, TextureLimits{64, 4096});  // exactly at both limits
    ASSERT_TRUE(exact.ok()) << exact.error().message;
    EXPECT_EQ((*exact)->width(), 64);

    // The JPEG path checks too: 8x16 against 8 per side.
    const std::vector<unsigned char> jpeg = two_block_jpeg();
    auto j = Texture::decode(jpeg.data(), jpeg.size(), "two_blocks.jpg", TextureLimits{8});
    ASSERT_FALSE(j.ok());
    EXPECT_EQ(j.error().code, ErrorCode::limit_exceeded);
    EXPECT_TRUE(mentions(j.error(), "8x16")) << j.error().message;
}

}  // namespace
