// Property: the lit mode's alpha-blended unlit draws (shaders::PbrUnlitBlended, the contact shadow's
// quad) draw the bytes shaders::Pbr draws for such a material, on every ISA: its scalar fragment()
// and its SIMD blend kernel (src/shade/blend_simd.cpp, CompiledBlendPass) alike.
// Adversarial for the kernel: a target of random colours and depths (every depth test), uvs that are
// NaN, huge or outside [0, 1], colours that are black (the kernel's lanes) or not, -0, infinite or NaN
// (the specification's lanes), alpha outside [0, 1], maps with every alpha, sampled as the kernel
// reads them (clamped, bilinear) and as it leaves to the specification (repeat, nearest, a uv
// transform), or no map; tiles narrower than a vector.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "facet/camera.hpp"
#include "facet/isa.hpp"
#include "facet/renderer.hpp"
#include "facet/shaders.hpp"
#include "support/pixels.hpp"

namespace {

using namespace facet;

constexpr int k_width = 131, k_height = 97;
constexpr float k_nan = std::numeric_limits<float>::quiet_NaN(), k_inf = std::numeric_limits<float>::infinity();

Mesh blended_mesh(std::uint64_t seed, int triangles) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f), size(0.05f, 0.6f);
    Mesh m;
    for (int t = 0; t < triangles; ++t) {
        const Vec3 centre{u(rng), u(rng), u(rng)};
        const float r = size(rng);
        for (int k = 0; k < 3; ++k) {
            const int i = t * 3 + k;
            m.positions.push_back(centre + Vec3{u(rng), u(rng), u(rng)} * r);
            m.normals.push_back({0, 1, 0});
            Vec2 uv{u(rng) * 0.8f + 0.5f, u(rng) * 0.8f + 0.5f};  // partly outside [0, 1]: clamped
            if (i % 61 == 0) uv.x = k_nan;
            if (i % 67 == 0) uv.y = 1e30f;
            if (i % 71 == 0) uv.x = -k_inf;
            m.uvs.push_back(uv);
            // Black mostly; the others go through the specification lane by lane.
            Vec4 c{0, 0, 0, unit(rng) * 1.5f - 0.2f};
            if (t % 13 == 0) c.x = unit(rng);
            if (i % 53 == 0) c.y = -0.0f;
            if (i % 59 == 0) c.z = k_inf;
            if (i % 83 == 0) c.w = k_nan;
            m.colours.push_back(c);
            m.indices.push_back(static_cast<std::uint32_t>(i));
        }
    }
    return m;
}

// With `sparse`, alpha 0 outside columns 6-10 and rows 4-6, as the contact shadow's map is 0 around
// the model's footprint.
std::shared_ptr<const Texture> alpha_map(bool sparse = false) {
    Image img{17, 11, std::vector<Rgba8>(17 * 11)};
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
        const std::size_t x = i % 17, y = i / 17;
        const bool zero = sparse && (x < 6 || x > 10 || y < 4 || y > 6);
        img.pixels[i] = {static_cast<std::uint8_t>(i * 29), static_cast<std::uint8_t>(i * 3), 0,
                         static_cast<std::uint8_t>(zero ? 0 : i * 47 + 5)};
    }
    return std::make_shared<const Texture>(std::move(img));
}

// A target of random colours, and the depths of the mesh drawn before in its own order with
// DepthTest::always (1 around it): each pixel holds its last triangle's depth, so that every depth
// test, equal included, passes some pixels and fails others.
void fill_target(Framebuffer& fb, const Camera& camera, const Mesh& occluders) {
    std::mt19937_64 rng(99);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int i = 0; i < k_width * k_height; ++i) {
        fb.colour_data()[i] = {static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                               static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng))};
        fb.depth_data()[i] = 1.0f;
    }
    ShadingUniforms u;
    u.clip_from_object = camera.projection(static_cast<float>(k_width) / static_cast<float>(k_height)) * camera.view();
    Renderer renderer({.threads = 1});
    DrawState state;
    state.cull = CullMode::none;
    state.depth_test = DepthTest::always;  // colours as they were; only the depths are wanted
    const shaders::Mask shader{MeshArrays::of(occluders), u};
    std::vector<Rgba8> colours(fb.colour_data(), fb.colour_data() + k_width * k_height);
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(occluders.positions.size()), occluders.indices}, shader);
    std::copy(colours.begin(), colours.end(), fb.colour_data());
}

template <class S>
std::vector<Rgba8> draw(const Mesh& mesh, const S& shader, const Camera& camera, DepthTest test, RendererConfig config) {
    Renderer renderer(config);
    Framebuffer fb(k_width, k_height);
    fill_target(fb, camera, mesh);
    DrawState state;
    state.cull = CullMode::none;
    state.blend = Blend::alpha;
    state.depth_write = false;
    state.depth_test = test;
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices}, shader);
    return {fb.colour_data(), fb.colour_data() + k_width * k_height};
}

struct Case {
    const char* name;
    bool textured;
    Sampler sampler;
    bool transformed;
    Vec4 base_colour;
    ToneMapping tone_mapping;
    bool sparse = false;  // the map's alpha only in its middle: the kernel skips tiles that sample none
};

TEST(CompiledBlendPass, UnlitBlendedDrawsWhatPbrDrawsOnEveryIsa) {
    facet_test::IsaGuard guard;
    const Mesh mesh = blended_mesh(5, 400);
    const std::shared_ptr<const Texture> map = alpha_map(), sparse_map = alpha_map(true);
    Camera camera;
    camera.position = {0.3f, 0.6f, 3.0f};
    camera.target = {0, 0, 0};
    ShadingUniforms u;
    u.clip_from_object = camera.projection(static_cast<float>(k_width) / static_cast<float>(k_height)) * camera.view();
    u.eye = camera.position;
    const Sampler shadow{Wrap::clamp, Wrap::clamp, Filter::bilinear};
    const Case cases[] = {
        {"the contact shadow's: black, clamped bilinear map", true, shadow, false, {0, 0, 0, 0.9f}, ToneMapping::neutral},
        {"the shadow's, its map's alpha only in the middle", true, shadow, false, {0, 0, 0, 0.9f}, ToneMapping::neutral, true},
        {"aces", true, shadow, false, {0, 0, 0, 1}, ToneMapping::aces},
        {"no map", false, shadow, false, {0, 0, 0, 0.7f}, ToneMapping::linear},
        {"not black: every lane by the specification", true, shadow, false, {0.4f, 0.2f, 0.9f, 1}, ToneMapping::neutral},
        {"repeat, nearest, transformed: the specification", true, {Wrap::repeat, Wrap::mirror, Filter::nearest}, true,
         {0, 0, 0, 1}, ToneMapping::neutral},
    };
    for (const Case& c : cases) {
        u.base_colour = c.base_colour;
        PbrUniforms p;
        p.environment = Environment::studio().get();
        p.tone_mapping = c.tone_mapping;
        p.unlit = true;
        if (c.textured) {
            p.base_colour.texture = c.sparse ? sparse_map.get() : map.get();
            p.base_colour.sampler = c.sampler;
            if (c.transformed) {
                const float m[6] = {0.8f, 0.6f, 0.25f, -0.6f, 0.8f, -1.5f};
                std::copy(m, m + 6, p.base_colour.transform.m);
                p.base_colour.transformed = true;
            }
        }
        const MeshArrays arrays = MeshArrays::of(mesh);
        const bool every_test = &c == &cases[0];  // the depth tests are the kernel's whatever the colour
        for (DepthTest test : {DepthTest::less, DepthTest::lequal, DepthTest::equal, DepthTest::greater, DepthTest::always}) {
            if (!every_test && test != DepthTest::less) continue;
            const std::string name = std::string(c.name) + ", depth test " + std::to_string(static_cast<int>(test));
            ASSERT_TRUE(select_isa("scalar"));
            const std::vector<Rgba8> reference = draw(mesh, shaders::Pbr{arrays, u, p}, camera, test, {.threads = 1, .tile_size = 64});
            std::vector<Rgba8> untouched(reference.size());
            {
                Framebuffer fb(k_width, k_height);
                fill_target(fb, camera, mesh);
                untouched.assign(fb.colour_data(), fb.colour_data() + k_width * k_height);
            }
            std::size_t blended = 0;
            for (std::size_t i = 0; i < reference.size(); ++i) blended += reference[i] != untouched[i];
            EXPECT_GT(blended, reference.size() / (c.sparse ? 200 : 20)) << name << ": the draw blends over part of the target";
            for (const std::string& isa : available_isas()) {
                ASSERT_TRUE(select_isa(isa));
                for (int tile : {8, 64}) {
                    const std::vector<Rgba8> out =
                        draw(mesh, shaders::PbrUnlitBlended{arrays, u, p}, camera, test, {.threads = 2, .tile_size = tile});
                    EXPECT_TRUE(out == reference) << name << " on " << isa << ", tile " << tile << ": "
                                                  << facet_test::first_difference(out, reference, k_width);
                }
            }
        }
    }
}

}  // namespace
