// The contact shadow (facet/contact_shadow.hpp): where its quad lies, that it is darkest under the
// model's base and fades out before the quad's edges, that a model lifted off the ground casts a
// fainter one, its blur (the rule's loop, bit for bit), and `--contact-shadow` on the command line
// (the lit mode's thumbnails' default).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "facet/contact_shadow.hpp"
#include "facet/math/transform.hpp"
#include "scene/box_blur.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace fs = std::filesystem;

// A unit cube (side 2) whose base is at y = `base`.
SceneObject cube(float base) {
    SceneObject o;
    o.mesh = make_cube(1.0f);
    o.model = translate({0, base + 1, 0});
    return o;
}

std::uint8_t alpha_at(const ContactShadow& s, float u, float v) {
    const Texture& t = *s.material.base_colour_texture;
    const Image& img = t.level(0);
    const int x = std::clamp(static_cast<int>(u * static_cast<float>(img.width)), 0, img.width - 1);
    const int y = std::clamp(static_cast<int>(v * static_cast<float>(img.height)), 0, img.height - 1);
    return img.at(x, y).a;
}

// The blur's rule as a plain loop: every texel the sum of its neighbours along the row (then the
// column), clamped at the edges, in order from -r to r, times 1 / (2r + 1).
std::vector<float> blurred_by_the_rule(std::vector<float> v, int n, int r) {
    std::vector<float> tmp(v.size());
    const float scale = 1.0f / static_cast<float>(2 * r + 1);
    for (int pass = 0; pass < 3; ++pass)
        for (int axis = 0; axis < 2; ++axis) {
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    float s = 0;
                    for (int k = -r; k <= r; ++k) {
                        const int t = std::clamp(i + k, 0, n - 1);
                        s += axis == 0 ? v[static_cast<std::size_t>(j * n + t)] : v[static_cast<std::size_t>(t * n + j)];
                    }
                    (axis == 0 ? tmp[static_cast<std::size_t>(j * n + i)] : tmp[static_cast<std::size_t>(i * n + j)]) = s * scale;
                }
            v.swap(tmp);
        }
    return v;
}

TEST(ContactShadow, BlurIsTheRulesLoopBitForBit) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (const auto& [n, r] : {std::pair{128, 4}, {1, 4}, {3, 5}, {17, 1}, {16, 0}, {40, 7}}) {
        std::vector<float> v(static_cast<std::size_t>(n * n));
        for (float& x : v) x = unit(rng) < 0.3f ? 0.0f : unit(rng) * unit(rng);  // runs of zeros, as under a model's edge
        const std::vector<float> expected = blurred_by_the_rule(v, n, r);
        detail::box_blur(v, n, r);
        std::vector<std::uint32_t> got_bits, expected_bits;
        for (float x : v) got_bits.push_back(std::bit_cast<std::uint32_t>(x));
        for (float x : expected) expected_bits.push_back(std::bit_cast<std::uint32_t>(x));
        EXPECT_EQ(got_bits, expected_bits) << n << " " << r;
    }
}

TEST(ContactShadow, ADarkPatchUnderTheBaseFadingBeforeTheEdges) {
    Renderer renderer({.threads = 2});
    const SceneObject o = cube(0.5f);
    const ObjectView view = view_of(o);
    const std::optional<ContactShadow> s = make_contact_shadow(renderer, {&view, 1}, 0.8f);
    ASSERT_TRUE(s);
    // A quad just below the base, centred under the cube, larger than it.
    ASSERT_EQ(s->mesh.positions.size(), 4u);
    for (const Vec3 p : s->mesh.positions) {
        EXPECT_LT(p.y, 0.5f);
        EXPECT_GT(p.y, 0.49f);
        EXPECT_GT(std::max(std::abs(p.x), std::abs(p.z)), 1.0f);
    }
    EXPECT_TRUE(s->material.unlit);
    EXPECT_EQ(s->material.alpha_mode, AlphaMode::blend);
    // Darkest under the cube (its bottom face touches the ground: the full opacity, 0.8), nothing
    // at the quad's corners.
    EXPECT_NEAR(alpha_at(*s, 0.5f, 0.5f), 204, 2);
    for (float c : {0.01f, 0.99f}) EXPECT_EQ(alpha_at(*s, c, c), 0);
    // Monotonic fade from the centre outward along a row.
    for (float u = 0.5f; u < 0.98f; u += 0.02f) EXPECT_GE(alpha_at(*s, u, 0.5f), alpha_at(*s, u + 0.02f, 0.5f)) << u;

    // A model lifted off the ground casts a fainter shadow: beside the cube a pebble whose base,
    // 0.4 lower, is the ground; the band is a quarter of the largest extent (2.4), so the cube's
    // base is 2/3 of the way up it.
    SceneObject pebble;
    pebble.mesh = make_cube(0.1f);
    pebble.model = translate({1.5f, 0.2f, 1.5f});
    const ObjectView both[2] = {view_of(o), view_of(pebble)};
    const std::optional<ContactShadow> lifted = make_contact_shadow(renderer, both, 0.8f);
    ASSERT_TRUE(lifted);
    EXPECT_LT(alpha_at(*lifted, 0.5f, 0.5f), alpha_at(*s, 0.5f, 0.5f) / 3);
    EXPECT_GT(alpha_at(*lifted, 0.5f, 0.5f), 0);

    EXPECT_FALSE(make_contact_shadow(renderer, {&view, 1}, 0.0f));
    EXPECT_FALSE(make_contact_shadow(renderer, {}, 0.8f));
}

TEST(ContactShadow, ThumbnailsOfTheLitModeHaveOneOthersDoNot) {
    const fs::path dir = facet_test::test_temp_dir("facet_shadow");
    const fs::path model = dir / "box.obj";
    facet_test::write_file(model, facet_test::k_box_obj);
    auto thumb = [&](const std::string& name, std::vector<std::string> options) {
        const fs::path out = dir / name;
        fs::create_directories(out);
        std::vector<std::string> args{"thumbs", model.string(), "-o", out.string(), "--size", "96", "--background", "1,1,1"};
        args.insert(args.end(), options.begin(), options.end());
        const facet_test::CliRun r = facet_test::run_facet(args);
        EXPECT_EQ(r.exit_code, 0) << r.all();
        return facet_test::decode_png(out / "box.obj.png");
    };
    const facet_test::DecodedPng with = thumb("with", {}), without = thumb("without", {"--contact-shadow", "0"});
    ASSERT_TRUE(with.ok() && without.ok()) << with.error << without.error;
    // Below the box (seen from above, azimuth 35, elevation 25) the white background darkens.
    std::size_t darker = 0, lighter = 0;
    for (std::size_t i = 0; i < with.rgba.size(); ++i) {
        darker += with.rgba[i].r < without.rgba[i].r;
        lighter += with.rgba[i].r > without.rgba[i].r;
    }
    EXPECT_GT(darker, 100u);
    EXPECT_EQ(lighter, 0u);
    // The top row is far from the ground: untouched.
    for (std::uint32_t x = 0; x < with.width; ++x) EXPECT_EQ(with.at(x, 0).r, without.at(x, 0).r);
    // Other modes draw none; a bad opacity is a usage error.
    const facet_test::DecodedPng normals = thumb("normals", {"--shading", "normals"});
    const facet_test::DecodedPng normals0 = thumb("normals0", {"--shading", "normals", "--contact-shadow", "0"});
    EXPECT_TRUE(normals.rgba == normals0.rgba);
    const facet_test::CliRun bad = facet_test::run_facet({"render", "--contact-shadow", "1.5", "-o", (dir / "x.png").string()});
    EXPECT_EQ(bad.exit_code, 2) << bad.all();
    EXPECT_NE(bad.err.find("--contact-shadow must be 0..1"), std::string::npos) << bad.all();
}

}  // namespace
