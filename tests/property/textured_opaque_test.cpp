// Property: the textured shaders without an alpha cutoff (TexturedOpaque, TextureUnlitOpaque), which
// cannot discard and so are drawn visible-only (hidden pixels never shaded), draw the bytes of the
// discarding ones (Textured, TextureUnlit) whenever the cutoff cannot discard (alpha_cutoff < 0, as
// render_scene binds every material but AlphaMode::mask): many overlapping textured triangles, both
// windings, at several thread counts and tile sizes.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "facet/camera.hpp"
#include "facet/renderer.hpp"
#include "facet/shaders.hpp"

namespace {

using namespace facet;

static_assert(detail::draws_visible_only<shaders::TexturedOpaque, Blend::none>());
static_assert(detail::draws_visible_only<shaders::TextureUnlitOpaque, Blend::none>());
static_assert(!detail::draws_visible_only<shaders::Textured, Blend::none>());
static_assert(!detail::draws_visible_only<shaders::TextureUnlit, Blend::none>());

Mesh overlapping_mesh(std::uint64_t seed, int triangles) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f), size(0.05f, 0.8f);
    Mesh m;
    for (int t = 0; t < triangles; ++t) {
        const Vec3 centre{u(rng) * 0.6f, u(rng) * 0.6f, u(rng) * 0.6f};
        const float r = size(rng);
        for (int k = 0; k < 3; ++k) {
            m.positions.push_back(centre + Vec3{u(rng), u(rng), u(rng)} * r);
            m.normals.push_back(Vec3{u(rng), u(rng), u(rng)});
            m.colours.push_back(Vec4{unit(rng), unit(rng), unit(rng), unit(rng)});
            m.uvs.push_back(Vec2{u(rng) * 3.0f, u(rng) * 3.0f});  // outside [0, 1] too: wrapping
        }
    }
    for (std::uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
    return m;
}

std::shared_ptr<const Texture> test_texture() {
    Image image;
    image.width = 37, image.height = 20;  // odd and even sides: every mip filter
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            image.pixels.push_back(Rgba8{std::uint8_t(x * 7), std::uint8_t(y * 12), std::uint8_t((x ^ y) * 5), std::uint8_t(100 + x)});
    return std::make_shared<const Texture>(std::move(image));
}

constexpr int k_width = 211, k_height = 149;

template <class S>
std::vector<Rgba8> render(const Mesh& mesh, const S& shader, RendererConfig config) {
    Renderer renderer(config);
    Framebuffer fb(k_width, k_height);
    fb.clear(Vec4{0.1f, 0.2f, 0.3f, 1.0f}, 1.0f);
    DrawState state;
    state.cull = CullMode::none;
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices}, shader);
    return {fb.colour_data(), fb.colour_data() + k_width * k_height};
}

template <class Opaque, class Cutoff>
void expect_same_bytes(const char* name) {
    const Mesh mesh = overlapping_mesh(11, 400);
    const std::shared_ptr<const Texture> texture = test_texture();
    Camera camera;
    camera.position = {0.3f, 0.5f, 2.6f};
    ShadingUniforms u;
    u.clip_from_object = camera.projection(static_cast<float>(k_width) / k_height) * camera.view();
    u.eye = camera.position;
    const TextureBinding tex{texture.get(), Sampler{Wrap::repeat, Wrap::mirror, Filter::trilinear}, -1.0f};
    const Opaque opaque{MeshArrays::of(mesh), u, tex};
    const Cutoff cutoff{MeshArrays::of(mesh), u, tex};
    const std::vector<Rgba8> reference = render(mesh, cutoff, {.threads = 1});
    std::size_t drawn = 0;
    for (Rgba8 c : reference) drawn += !(c.r == 26 && c.g == 51 && c.b == 77);
    EXPECT_GT(drawn, static_cast<std::size_t>(k_width * k_height / 2)) << name << ": the triangles cover the image";
    for (int threads : {1, 3})
        for (int tile : {8, 64})
            EXPECT_TRUE(render(mesh, opaque, {.threads = threads, .tile_size = tile}) == reference)
                << name << ", threads " << threads << ", tile " << tile;
}

TEST(TexturedOpaque, DrawsTheBytesOfTexturedWithoutACutoff) {
    expect_same_bytes<shaders::TexturedOpaque, shaders::Textured>("Textured");
}
TEST(TexturedOpaque, TextureUnlitOpaqueDrawsTheBytesOfTextureUnlitWithoutACutoff) {
    expect_same_bytes<shaders::TextureUnlitOpaque, shaders::TextureUnlit>("TextureUnlit");
}

}  // namespace
