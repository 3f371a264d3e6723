// The lit mode: the tone mappers and sRGB against their published formulas, the environment's maps
// and split-sum table, the HDR loader's errors, and what rendered images must show: a generated
// glTF grid of spheres from metallic 0..1 by roughness 0..1 (the highlight widens and dims with
// roughness; metals take the environment's colour, tinted by their own), and each texture map of a
// generated glTF doing what it is for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "facet/environment.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "facet/tone_mapping.hpp"
#include "shade/environment_prefilter.hpp"
#include "support/gltf_writer.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
using namespace facet_test;
namespace fs = std::filesystem;

// ---- the display transform ------------------------------------------------------------------------

// Khronos PBR Neutral as published (the reference GLSL), in double.
void neutral_reference(const double in[3], double out[3]) {
    const double start = 0.8 - 0.04, desaturation = 0.15;
    double c[3] = {in[0], in[1], in[2]};
    const double x = std::min({c[0], c[1], c[2]});
    const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    for (double& v : c) v -= offset;
    const double peak = std::max({c[0], c[1], c[2]});
    if (peak < start) {
        std::copy(c, c + 3, out);
        return;
    }
    const double d = 1 - start;
    const double new_peak = 1 - d * d / (peak + d - start);
    for (double& v : c) v *= new_peak / peak;
    const double g = 1 - 1 / (desaturation * (peak - new_peak) + 1);
    for (int k = 0; k < 3; ++k) out[k] = c[k] * (1 - g) + new_peak * g;
}

TEST(ToneMapping, PbrNeutralIsItsPublishedFormula) {
    for (double r = 0; r < 20; r += 0.37)
        for (double g : {0.0, 0.01, 0.05, 0.3, 0.76, 0.9, 2.0, 9.0})
            for (double b : {0.0, 0.07, 0.5, 1.5, 40.0}) {
                const double in[3] = {r, g, b};
                double want[3];
                neutral_reference(in, want);
                const Vec3 got = tone_map_pbr_neutral({static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)});
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[static_cast<std::size_t>(k)], want[k], 2e-6) << r << "," << g << "," << b;
            }
    // Its promises: below the compression point a grey is kept but for the 0.04 offset, white
    // stays white, and highlights approach 1 without reaching it.
    EXPECT_NEAR(tone_map_pbr_neutral({0.5f, 0.5f, 0.5f}).x, 0.46f, 1e-6f);
    EXPECT_NEAR(tone_map_pbr_neutral({1e6f, 1e6f, 1e6f}).x, 1.0f, 1e-5f);
    EXPECT_LT(tone_map_pbr_neutral({4, 4, 4}).x, 1.0f);
}

TEST(ToneMapping, AcesIsThreeJsFit) {
    auto fit = [](double v) { return (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081); };
    for (double v : {0.0, 0.05, 0.18, 0.5, 1.0, 3.0, 30.0}) {
        // A grey: the input matrix's rows and the output matrix's rows each sum to (almost) 1.
        const double in = v / 0.6;
        const double rows_in[3] = {0.59719 + 0.35458 + 0.04823, 0.07600 + 0.90834 + 0.01566, 0.02840 + 0.13383 + 0.83777};
        const double f[3] = {fit(in * rows_in[0]), fit(in * rows_in[1]), fit(in * rows_in[2])};
        const double out_r = 1.60475 * f[0] - 0.53108 * f[1] - 0.07367 * f[2];
        const Vec3 got = tone_map_aces({static_cast<float>(v), static_cast<float>(v), static_cast<float>(v)});
        EXPECT_NEAR(got.x, std::clamp(out_r, 0.0, 1.0), 2e-6) << v;
    }
    EXPECT_EQ(tone_map_aces({100, 100, 100}).x, 1.0f);  // clamped
}

TEST(ToneMapping, SrgbTransferFunctions) {
    for (int i = 0; i <= 1000; ++i) {
        const double c = i / 1000.0;
        const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
        EXPECT_NEAR(linear_to_srgb(static_cast<float>(c)), encoded, 3e-6) << c;
        const double decoded = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        EXPECT_NEAR(srgb_to_linear(static_cast<float>(c)), decoded, 3e-6) << c;
    }
    EXPECT_EQ(linear_to_srgb(-1.0f), 0.0f);
    EXPECT_EQ(linear_to_srgb(std::nanf("")), 0.0f);
    EXPECT_NEAR(linear_to_srgb(7.0f), 1.0f, 1e-6f);
    ToneMapping t;
    EXPECT_TRUE(parse_tone_mapping("aces", t) && t == ToneMapping::aces);
    EXPECT_FALSE(parse_tone_mapping("filmic", t));
    EXPECT_STREQ(to_string(ToneMapping::neutral), "neutral");
}

// ---- the environment ----------------------------------------------------------------------------

TEST(Environment, OctahedralCoordinatesRoundTrip) {
    for (float u = 0.01f; u < 1; u += 0.0317f)
        for (float v = 0.01f; v < 1; v += 0.0293f) {
            const Vec3 d = octahedral_direction({u, v});
            EXPECT_NEAR(length(d), 1.0f, 1e-6f);
            const Vec2 back = octahedral_uv(d);
            EXPECT_NEAR(back.x, u, 2e-6f);
            EXPECT_NEAR(back.y, v, 2e-6f);
        }
    const Vec2 up = octahedral_uv({0, 1, 0}), zero = octahedral_uv({0, 0, 0});
    EXPECT_EQ(up.x, 0.5f);
    EXPECT_EQ(zero.y, 0.5f);
}

TEST(Environment, AUniformSkyLightsEveryNormalAndReflectsItself) {
    const auto e = Environment::from_function([](Vec3) { return Vec3{0.2f, 0.5f, 1.5f}; });
    for (Vec3 n : {Vec3{0, 1, 0}, Vec3{0, -1, 0}, normalize(Vec3{1, 2, -3}), normalize(Vec3{-0.3f, 0.1f, 0.9f})}) {
        // E / pi of a uniform L is L, for every normal; every level of the prefilter keeps L.
        const Vec3 d = e->diffuse(n);
        EXPECT_NEAR(d.x, 0.2f, 1e-3f);
        EXPECT_NEAR(d.z, 1.5f, 5e-3f);
        for (float lod = 0; lod <= 5; lod += 0.5f) EXPECT_NEAR(e->specular(n, lod).y, 0.5f, 1e-5f) << lod;
    }
}

TEST(Environment, StudioIsBuiltOnceWithTheSameBits) {
    const auto a = Environment::studio(), b = Environment::studio();
    EXPECT_EQ(a.get(), b.get());
    const auto again = Environment::from_function([&](Vec3 d) { return a->radiance(d); });
    // Made from the studio's own sharpest level: its texel centres are read back exactly.
    EXPECT_EQ(a->level(0).size, again->level(0).size);
    // Brighter above than below, and brightest toward the key light (above left of the front).
    EXPECT_GT(a->diffuse({0, 1, 0}).x, a->diffuse({0, -1, 0}).x);
    EXPECT_GT(a->diffuse(normalize(Vec3{-0.65f, 0.55f, 0.55f})).x, a->diffuse(normalize(Vec3{0.65f, 0.55f, -0.55f})).x);
}

// The studio and the split-sum table are constants computed when the library was built
// (src/shade/bake): they must be what the library's code computes now, bit for bit.
TEST(Environment, BakedStudioAndSplitSumAreTheComputedOnes) {
    const auto baked = Environment::studio();
    const auto computed = Environment::from_function(environment_detail::studio_radiance);
    ASSERT_EQ(baked->texels().size(), computed->texels().size());
    EXPECT_EQ(0, std::memcmp(baked->texels().data(), computed->texels().data(), baked->texels().size() * sizeof(float)));
    for (int l = 0; l < Environment::k_levels; ++l) {
        EXPECT_EQ(baked->level(l).size, computed->level(l).size) << l;
        EXPECT_EQ(baked->level(l).offset, computed->level(l).offset) << l;
    }
    EXPECT_EQ(0, std::memcmp(baked->diffuse_sh().data(), computed->diffuse_sh().data(), sizeof(baked->diffuse_sh())));
    const std::vector<float> table = environment_detail::make_split_sum_table();
    ASSERT_EQ(split_sum_table().size(), table.size());
    EXPECT_EQ(0, std::memcmp(split_sum_table().data(), table.data(), table.size() * sizeof(float)));
}

TEST(Environment, SplitSumTableIsABrdfsScaleAndBias) {
    const std::vector<float>& t = split_sum_table();
    ASSERT_EQ(t.size(), static_cast<std::size_t>(k_split_sum_size * k_split_sum_size * 2));
    for (std::size_t i = 0; i < t.size(); i += 2) {
        EXPECT_GE(t[i], 0.0f);
        EXPECT_GE(t[i + 1], 0.0f);
        EXPECT_LE(t[i] + t[i + 1], 1.001f);  // no energy created (but for the sampling's noise)
    }
    // Smooth and seen head-on, a GGX surface reflects F0: A near 1, B near 0; at grazing angles the
    // Fresnel bias B grows.
    const Vec2 head_on = split_sum(1.0f, 0.0f), grazing = split_sum(0.05f, 0.0f);
    EXPECT_GT(head_on.x, 0.95f);
    EXPECT_LT(head_on.y, 0.02f);
    EXPECT_GT(grazing.y, head_on.y + 0.1f);
    // Rougher surfaces lose energy to shadowing and masking: A + B decreases.
    EXPECT_GT(split_sum(0.5f, 0.1f).x + split_sum(0.5f, 0.1f).y, split_sum(0.5f, 0.9f).x + split_sum(0.5f, 0.9f).y);
}

// A Radiance HDR file of width x height pixels of one colour (flat RGBE scanlines).
std::string hdr_file(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t e) {
    std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n";
    for (int i = 0; i < width * height; ++i) s += std::string{static_cast<char>(r), static_cast<char>(g), static_cast<char>(b), static_cast<char>(e)};
    return s;
}

TEST(Environment, HdrFilesLoadAndBadOnesAreErrorsNamingThem) {
    const fs::path dir = test_temp_dir("facet_lit");
    // 128 * 2^(129 - 136) = 1.0 in every channel (RGBE: mantissa * 2^(e - 128 - 8)).
    const std::string good = write_file(dir / "grey.hdr", hdr_file(16, 8, 128, 128, 128, 129));
    const Result<std::shared_ptr<const Environment>> e = Environment::load_hdr(good);
    ASSERT_TRUE(e) << e.error().message;
    EXPECT_NEAR((*e)->diffuse({0, 1, 0}).y, 1.0f, 2e-3f);
    EXPECT_NEAR((*e)->radiance(normalize(Vec3{1, -2, 3})).x, 1.0f, 1e-6f);

    struct Bad {
        std::string path;
        ErrorCode code;
        const char* says;
    };
    const Bad bad[] = {
        {(dir / "missing.hdr").string(), ErrorCode::io, "cannot open"},
        {write_file(dir / "image.png", "\x89PNG\r\n\x1a\nnot really"), ErrorCode::bad_format,
         "not a Radiance HDR image"},
        {write_file(dir / "cut.hdr", hdr_file(16, 8, 1, 2, 3, 129).substr(0, 70)), ErrorCode::bad_format, "not a readable HDR image"},
        {write_file(dir / "empty.hdr", ""), ErrorCode::bad_format, "not a Radiance HDR image"},
        {dir.string(), ErrorCode::io, "cannot read"},  // a directory: opens, but cannot be read
    };
    for (const Bad& b : bad) {
        const auto r = Environment::load_hdr(b.path);
        ASSERT_FALSE(r) << b.path;
        EXPECT_EQ(r.error().code, b.code) << r.error().message;
        EXPECT_NE(r.error().message.find(b.path), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(b.says), std::string::npos) << r.error().message;
    }
    const auto large = Environment::load_hdr(good, 100);
    ASSERT_FALSE(large);
    EXPECT_EQ(large.error().code, ErrorCode::limit_exceeded);
    EXPECT_NE(large.error().message.find("16x8"), std::string::npos) << large.error().message;
}

// ---- rendered properties -------------------------------------------------------------------------

// Linear-light luminance of a displayed pixel (the image is sRGB-encoded).
float luminance(Rgba8 c) {
    return 0.2126f * srgb_to_linear(c.r / 255.0f) + 0.7152f * srgb_to_linear(c.g / 255.0f) + 0.0722f * srgb_to_linear(c.b / 255.0f);
}

struct Rendered {
    Image image;
    Camera camera;
};

Rendered render(const Scene& scene, int width, int height, const RenderSettings& settings) {
    Renderer renderer({.threads = 2});
    Framebuffer target(width, height);
    const Camera camera = make_camera(scene, ViewSpec{}, static_cast<float>(width) / static_cast<float>(height));
    render_scene(renderer, target, scene, camera, settings);
    return {target.to_image(), camera};
}

// The pixels of the sphere of radius 1 at `centre`, within 0.9 of its radius on screen.
struct Pixel {
    Vec2 at;
    Rgba8 colour;
};
std::vector<Pixel> sphere_pixels(const Rendered& r, Vec3 centre) {
    const float aspect = static_cast<float>(r.image.width) / static_cast<float>(r.image.height);
    const Mat4 clip = r.camera.projection(aspect) * r.camera.view();
    auto screen = [&](Vec3 p) {
        const Vec4 c = clip * Vec4(p, 1);
        return Vec2{(c.x / c.w * 0.5f + 0.5f) * static_cast<float>(r.image.width), (0.5f - c.y / c.w * 0.5f) * static_cast<float>(r.image.height)};
    };
    const Vec2 s = screen(centre);
    const float radius = 0.9f * length(screen(centre + Vec3{0, 1, 0}) - s);
    std::vector<Pixel> out;
    for (int y = 0; y < r.image.height; ++y)
        for (int x = 0; x < r.image.width; ++x) {
            const Vec2 p{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
            if (length(p - s) < radius) out.push_back({p, r.image.at(x, y)});
        }
    return out;
}

// A sphere's highlight: its brightest luminance, and its spread, the root mean square distance
// from its centroid, each pixel weighted by how far it is above a tenth of the way from the
// sphere's median luminance to the peak (which leaves out the faint Fresnel rim of a dark sphere).
struct Highlight {
    float peak, spread;
};

Highlight highlight_of(const std::vector<Pixel>& pixels) {
    std::vector<float> l;
    for (const Pixel& p : pixels) l.push_back(luminance(p.colour));
    std::vector<float> sorted = l;
    std::sort(sorted.begin(), sorted.end());
    const float floor = sorted[sorted.size() / 2] + (sorted.back() - sorted[sorted.size() / 2]) / 10;
    double weight = 0, cx = 0, cy = 0, moment = 0;
    for (std::size_t i = 0; i < l.size(); ++i) {
        const double w = std::max(0.0f, l[i] - floor);
        weight += w, cx += w * pixels[i].at.x, cy += w * pixels[i].at.y;
    }
    cx /= weight, cy /= weight;
    for (std::size_t i = 0; i < l.size(); ++i) {
        const double dx = pixels[i].at.x - cx, dy = pixels[i].at.y - cy;
        moment += std::max(0.0f, l[i] - floor) * (dx * dx + dy * dy);
    }
    return {sorted.back(), static_cast<float>(std::sqrt(moment / weight))};
}

// One small bright disc light above the front, on black: its reflection is each sphere's highlight.
std::shared_ptr<const Environment> spotlight(Vec3 colour) {
    return Environment::from_function([colour](Vec3 d) {
        const float c = dot(d, normalize(Vec3{-0.3f, 0.4f, 1.0f}));
        const float w = clamp((c - 0.975f) / 0.01f, 0.0f, 1.0f);
        return colour * (20 * w) + Vec3{0.02f, 0.02f, 0.02f};
    });
}

Scene load_grid(const fs::path& dir, int rows, int columns, const float (&colour)[3]) {
    const Result<LoadedModel> r = load_model(write_gltf(dir / "grid.gltf", sphere_grid(rows, columns, 2.5f, colour)));
    EXPECT_TRUE(r) << r.error().message;
    return r ? std::move(r->scene) : Scene{};
}

Vec3 grid_centre(int row, int column, int rows, int columns) {
    return {(static_cast<float>(column) - static_cast<float>(columns - 1) / 2) * 2.5f,
            (static_cast<float>(rows - 1) / 2 - static_cast<float>(row)) * 2.5f, 0};
}

// Per row of `rows` x `columns` spheres of `colour`: each sphere's highlight is dimmer and wider
// than the one before it, smoother, in the row.
void expect_highlights_widen_and_dim(const fs::path& dir, int rows, int columns, const float (&colour)[3], int first_row,
                                     float exposure) {
    const Scene scene = load_grid(dir, rows, columns, colour);
    ASSERT_EQ(scene.objects.size(), static_cast<std::size_t>(rows * columns));
    RenderSettings settings;
    settings.environment = spotlight({1, 1, 1});
    settings.tone_mapping = ToneMapping::linear;  // no roll-off: peaks compare as rendered,
    settings.exposure = exposure;                 // and none clipped
    const Rendered r = render(scene, 1000, 200 * rows, settings);
    for (int row = first_row; row < rows; ++row) {
        std::vector<Highlight> h;
        for (int c = 0; c < columns; ++c) h.push_back(highlight_of(sphere_pixels(r, grid_centre(row, c, rows, columns))));
        for (std::size_t c = 1; c < h.size(); ++c) {
            SCOPED_TRACE("metallic " + std::to_string(scene.objects[static_cast<std::size_t>(row * columns)].material.metallic) +
                         ", roughness " + std::to_string(scene.objects[c].material.roughness));
            EXPECT_LT(h[c].peak, h[c - 1].peak);      // dims
            EXPECT_GT(h[c].spread, h[c - 1].spread);  // widens
        }
    }
}

TEST(LitMode, SphereGridHighlightWidensAndDimsWithRoughness) {
    const fs::path dir = test_temp_dir("facet_lit");
    // Metallic 0, 0.5 and 1 by roughness 0, 0.25 ... 1: the metals' highlights (a white dielectric's
    // is lost in its diffuse light), and black dielectrics, whose light is all highlight.
    const Scene check = load_grid(dir, 3, 5, {0.9f, 0.9f, 0.9f});
    ASSERT_EQ(check.objects.size(), 15u);
    EXPECT_EQ(check.objects[5].material.metallic, 0.5f);  // row 1
    EXPECT_EQ(check.objects[3].material.roughness, 0.75f);  // column 3
    expect_highlights_widen_and_dim(dir, 3, 5, {0.9f, 0.9f, 0.9f}, 1, 0.03f);
    expect_highlights_widen_and_dim(dir, 1, 5, {0.0f, 0.0f, 0.0f}, 0, 0.5f);
}

// Hue-free measure of how far a pixel is from grey: (max - min) / max of its channels.
float saturation(Rgba8 c) {
    const int hi = std::max({c.r, c.g, c.b}), lo = std::min({c.r, c.g, c.b});
    return hi == 0 ? 0.0f : static_cast<float>(hi - lo) / static_cast<float>(hi);
}

Rgba8 brightest(const std::vector<Pixel>& pixels) {
    return std::max_element(pixels.begin(), pixels.end(), [](const Pixel& a, const Pixel& b) {
               return luminance(a.colour) < luminance(b.colour);
           })->colour;
}

TEST(LitMode, MetalsTakeTheEnvironmentsColourTintedByTheirOwn) {
    const fs::path dir = test_temp_dir("facet_lit");
    RenderSettings settings;
    settings.exposure = 0.03f;
    settings.tone_mapping = ToneMapping::linear;
    // A white metal under an orange light reflects orange, in the light's proportions.
    settings.environment = spotlight({1.0f, 0.5f, 0.1f});
    const Rendered white = render(load_grid(dir, 2, 2, {1, 1, 1}), 400, 400, settings);
    const Rgba8 metal = brightest(sphere_pixels(white, grid_centre(1, 0, 2, 2)));
    EXPECT_GT(metal.r, metal.g);
    EXPECT_GT(metal.g, metal.b);
    EXPECT_NEAR(srgb_to_linear(metal.g / 255.0f) / srgb_to_linear(metal.r / 255.0f), 0.5f, 0.03f);
    // Under a white light an orange metal's highlight is orange, an orange dielectric's white
    // (Fresnel's 4% of every colour alike, over a little orange diffuse light).
    settings.environment = spotlight({1, 1, 1});
    const Rendered orange = render(load_grid(dir, 2, 2, {0.9f, 0.4f, 0.1f}), 400, 400, settings);
    const Rgba8 dielectric = brightest(sphere_pixels(orange, grid_centre(0, 0, 2, 2)));
    const Rgba8 orange_metal = brightest(sphere_pixels(orange, grid_centre(1, 0, 2, 2)));
    EXPECT_LT(saturation(dielectric), 0.3f) << int{dielectric.r} << "," << int{dielectric.g} << "," << int{dielectric.b};
    EXPECT_GT(saturation(orange_metal), 0.6f) << int{orange_metal.r} << "," << int{orange_metal.g} << "," << int{orange_metal.b};
    EXPECT_GT(saturation(orange_metal), 2 * saturation(dielectric));
}

// ---- each texture map's effect ---------------------------------------------------------------------

Image flat_image(Rgba8 c) { return Image{4, 4, std::vector<Rgba8>(16, c)}; }

// The centre pixel of the quad of `material` (images given), rendered under `environment`.
Rgba8 quad_centre(const fs::path& dir, const GltfMaterial& material, const std::vector<Image>& images,
                  std::shared_ptr<const Environment> environment = nullptr, bool mirrored = false) {
    GltfDocument doc;
    doc.images = images;
    doc.materials = {material};
    doc.nodes.push_back({facing_quad(mirrored), 0, {}});
    static int n = 0;
    const Result<LoadedModel> m = load_model(write_gltf(dir / ("quad" + std::to_string(n++) + ".gltf"), doc));
    EXPECT_TRUE(m) << m.error().message;
    if (!m) return {};
    RenderSettings settings;
    settings.environment = std::move(environment);
    const Rendered r = render(m->scene, 64, 64, settings);
    return r.image.at(32, 32);
}

bool same(Rgba8 a, Rgba8 b) { return a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a; }

TEST(LitMode, EachTextureMapDoesWhatItIsFor) {
    const fs::path dir = test_temp_dir("facet_lit");
    GltfMaterial plain;
    plain.metallic = 0, plain.roughness = 0.6f;
    const Rgba8 untextured = quad_centre(dir, plain, {});

    // Base colour: a red map makes the quad red.
    GltfMaterial base = plain;
    base.base_colour_texture.image = 0;
    const Rgba8 red = quad_centre(dir, base, {flat_image({255, 0, 0, 255})});
    EXPECT_GT(red.r, 3 * red.g);
    EXPECT_NEAR(red.r, untextured.r, 30);

    // Metallic-roughness: B times metallic, G times roughness. Under factors (1, 0.3), a map of
    // B = 0, G = 255 draws exactly the factors (0, 0.3), and B = G = 255 the factors (1, 0.3).
    GltfMaterial mr = plain;
    mr.base_colour[1] = mr.base_colour[2] = 0.2f;  // red: a metal reflects red, a dielectric white
    mr.metallic = 1, mr.roughness = 0.3f;
    mr.metallic_roughness_texture.image = 0;
    GltfMaterial dielectric = mr, metal = mr;
    dielectric.metallic_roughness_texture.image = metal.metallic_roughness_texture.image = -1;
    dielectric.metallic = 0;
    const Rgba8 as_dielectric = quad_centre(dir, mr, {flat_image({0, 255, 0, 255})});
    const Rgba8 as_metal = quad_centre(dir, mr, {flat_image({0, 255, 255, 255})});
    EXPECT_TRUE(same(as_dielectric, quad_centre(dir, dielectric, {})));
    EXPECT_TRUE(same(as_metal, quad_centre(dir, metal, {})));
    EXPECT_FALSE(same(as_metal, as_dielectric));

    // Occlusion: R = 0 at full strength leaves only the emissive term (here none): black; at
    // strength 0 the map does nothing.
    GltfMaterial occluded = plain;
    occluded.occlusion_texture.image = 0;
    const Rgba8 dark = quad_centre(dir, occluded, {flat_image({0, 0, 0, 255})});
    EXPECT_EQ(dark.r + dark.g + dark.b, 0);
    occluded.occlusion_strength = 0;
    EXPECT_TRUE(same(quad_centre(dir, occluded, {flat_image({0, 0, 0, 255})}), untextured));

    // Emissive: a black, fully occluded quad glows with its emissive map times the factor.
    GltfMaterial glowing = plain;
    glowing.base_colour[0] = glowing.base_colour[1] = glowing.base_colour[2] = 0;
    glowing.occlusion_texture.image = 0;
    glowing.emissive_texture.image = 1;
    glowing.emissive[0] = glowing.emissive[1] = glowing.emissive[2] = 1;
    const Rgba8 glow = quad_centre(dir, glowing, {flat_image({0, 0, 0, 255}), flat_image({0, 255, 0, 255})});
    EXPECT_GT(glow.g, 150);
    EXPECT_GT(glow.g, 4 * glow.r);  // (PBR Neutral desaturates a bright green a little toward white)

    // Normal map: under a light from +X only, a normal tilted toward +X (the map's +x along the
    // tangent, +u) is brighter than the flat map, one tilted away darker; with u mirrored the
    // tangent points to -X, and the same map tilts the other way.
    const auto from_the_right = Environment::from_function([](Vec3 d) {
        return d.x > 0.3f ? Vec3{2, 2, 2} : Vec3{0.01f, 0.01f, 0.01f};
    });
    GltfMaterial mapped = plain;
    mapped.normal_texture.image = 0;
    const Rgba8 flat = quad_centre(dir, mapped, {flat_image({128, 128, 255, 255})}, from_the_right);
    const Rgba8 toward = quad_centre(dir, mapped, {flat_image({230, 128, 200, 255})}, from_the_right);
    const Rgba8 away = quad_centre(dir, mapped, {flat_image({25, 128, 200, 255})}, from_the_right);
    const Rgba8 mirrored = quad_centre(dir, mapped, {flat_image({230, 128, 200, 255})}, from_the_right, true);
    EXPECT_GT(luminance(toward), luminance(flat) + 0.02f);
    EXPECT_LT(luminance(away), luminance(flat) - 0.02f);
    EXPECT_LT(luminance(mirrored), luminance(flat) - 0.02f);
}

}  // namespace
