// Property: the built-in shaders' compiled visible-pixel pass (src/shade/visible_simd*) draws the
// bytes of the scalar specification (detail::shade_visible: fragment() once per visible pixel, what
// "scalar" runs) on every ISA the CPU runs.
// The mesh is random and adversarial for the shaders' arithmetic: normals of every length including
// zero, huge and NaN ones, colours outside [0, 1], infinite and NaN ones, triangles of every size,
// facing both ways, seen in perspective; targets whose width is not a multiple of a vector; tiles
// narrower than a vector; and lights whose direction is NaN. For the lit mode also uvs that are
// NaN or huge, tangents of zero length or NaN, every map (with a uv transform) and every tone mapper.
#include <gtest/gtest.h>

#include <algorithm>
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

Mesh adversarial_mesh(std::uint64_t seed, int triangles) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f), size(0.01f, 0.5f);
    Mesh m;
    for (int t = 0; t < triangles; ++t) {
        const Vec3 centre{u(rng), u(rng), u(rng)};
        const float r = size(rng);
        for (int k = 0; k < 3; ++k) {
            m.positions.push_back(centre + Vec3{u(rng), u(rng), u(rng)} * r);
            Vec3 n{u(rng), u(rng), u(rng)};
            switch ((t * 3 + k) % 97) {
                case 0: n = {}; break;                                           // zero: normalize_rare
                case 1: n = n * 1e30f; break;                                    // squared length overflows
                case 2: n.y = std::numeric_limits<float>::quiet_NaN(); break;    // NaN
                case 3: n = n * 1e-30f; break;                                   // squared length underflows
                case 4: n = n * 1e-21f; break;                                   // squares subnormal
                case 5: n = n * 1e-18f; break;                                   // just above the Lambert lanes' least length
                default: break;
            }
            m.normals.push_back(n);
            Vec4 c{unit(rng) * 1.4f - 0.2f, unit(rng), unit(rng), unit(rng)};
            switch ((t * 3 + k) % 89) {
                case 0: c.x = std::numeric_limits<float>::quiet_NaN(); break;  // to_rgba8 maps NaN to 0
                case 1: c.y = std::numeric_limits<float>::infinity(); break;
                case 2: c.z = -std::numeric_limits<float>::infinity(); break;
                case 3: c.w = -0.0f; break;
                default: break;
            }
            m.colours.push_back(c);
        }
    }
    for (std::uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
    // For the lit mode's maps: uvs that repeat, huge and NaN ones; tangents of every length and side.
    std::mt19937_64 more(seed + 1);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        Vec2 uv{u(more) * 3, u(more) * 3};
        if (i % 71 == 0) uv.x = std::numeric_limits<float>::quiet_NaN();
        if (i % 73 == 0) uv.y = 1e30f;
        m.uvs.push_back(uv);
        Vec4 t{u(more), u(more), u(more), i % 2 ? 1.0f : -1.0f};
        if (i % 79 == 0) t = {0, 0, 0, 1};
        if (i % 83 == 0) t.z = std::numeric_limits<float>::quiet_NaN();
        m.tangents.push_back(t);
    }
    return m;
}

// grey: the lambert mode's white key light, no fill, a grey base colour (the Lambert kernels then
// compute one channel for three and leave the dark fill out); grey_nan_fill and grey_huge_fill: the
// same with a NaN fill direction, and one so long that dot(n, fill) overflows (0 * inf: NaN), which
// the kernels must not leave out. grey_dim_key: a grey key light of colour 0.5 (key * k is not k);
// grey_bright: one of 1.2 on a brighter grey, whose colours pass 1 (to_rgba8's clamps then count).
enum class Lights { ordinary, nan_fill, grey, grey_nan_fill, grey_huge_fill, grey_dim_key, grey_bright };

ShadingUniforms uniforms(int width, int height, float shininess, Lights lights = Lights::ordinary) {
    Camera camera;
    camera.position = {0.4f, 0.7f, 3.2f};
    camera.target = {0, 0, 0};
    ShadingUniforms u;
    u.clip_from_object = camera.projection(static_cast<float>(width) / static_cast<float>(height)) * camera.view();
    u.eye = camera.position;
    u.key = {normalize(Vec3{0.3f, 0.8f, 0.6f}), {1.0f, 0.97f, 0.92f}};
    u.fill = {normalize(Vec3{-0.7f, 0.1f, 0.3f}), {0.25f, 0.28f, 0.35f}};
    u.specular = 0.35f;
    u.base_colour = {0.9f, 0.7f, 1.3f, 0.8f};
    u.shininess = shininess;
    // max(dot(n, l), 0) of a NaN is NaN (and the colour 0), not 0: the lanes' max must keep it.
    if (lights == Lights::grey || lights == Lights::grey_nan_fill || lights == Lights::grey_huge_fill ||
        lights == Lights::grey_dim_key || lights == Lights::grey_bright) {
        u.key.colour = {1, 1, 1};
        u.fill.colour = {0, 0, 0};
        u.base_colour = {0.8f, 0.8f, 0.8f, 0.9f};
    }
    if (lights == Lights::grey_dim_key) u.key.colour = {0.5f, 0.5f, 0.5f};
    if (lights == Lights::grey_bright) u.key.colour = {1.2f, 1.2f, 1.2f}, u.base_colour = {0.95f, 0.95f, 0.95f, 1.0f};
    if (lights == Lights::nan_fill || lights == Lights::grey_nan_fill)
        u.fill.direction.y = std::numeric_limits<float>::quiet_NaN();
    if (lights == Lights::grey_huge_fill) u.fill.direction = {3e38f, 3e38f, 3e38f};
    return u;
}

// The same shader, made to see every fragment: a different type, so not a compiled one.
template <class S>
struct EveryFragment : S {
    static constexpr bool k_shade_hidden = true;
};

constexpr int k_width = 203, k_height = 157;

template <class S>
std::vector<Rgba8> render(const Mesh& mesh, RendererConfig config, const S& shader) {
    Renderer renderer(config);
    Framebuffer fb(k_width, k_height);
    fb.clear(Vec4{0.1f, 0.2f, 0.3f, 1.0f}, 1.0f);
    DrawState state;
    state.cull = CullMode::none;
    renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices}, shader);
    return {fb.colour_data(), fb.colour_data() + k_width * k_height};
}

template <class S>
std::vector<Rgba8> render(const Mesh& mesh, RendererConfig config, float shininess = 40.0f,
                          Lights lights = Lights::ordinary) {
    return render(mesh, config, S{MeshArrays::of(mesh), uniforms(k_width, k_height, shininess, lights)});
}

template <class S>
struct Wrapped : S {};

// `make(mesh)` gives the shader to draw the mesh with.
template <class S, class Make>
void expect_every_isa_draws_what_scalar_draws(const char* name, const Make& make) {
    static_assert(detail::CompiledVisiblePass<S>::available);
    facet_test::IsaGuard guard;
    const Mesh mesh = adversarial_mesh(7, 1500);
    const S shader = make(mesh);
    // The specification: "scalar" runs detail::shade_visible, fragment() once per visible pixel.
    // (That it draws what the one-pass order draws is Determinism's business; rendering the one-pass
    // order here too would instantiate it for every shader, a minute of compile time under ASan.)
    ASSERT_TRUE(select_isa("scalar"));
    const std::vector<Rgba8> reference = render(mesh, {.threads = 1, .tile_size = 64}, shader);
    std::size_t drawn = 0;
    for (const Rgba8 c : reference) drawn += !(c.r == 26 && c.g == 51 && c.b == 77);
    EXPECT_GT(drawn, static_cast<std::size_t>(k_width * k_height / 2)) << name << ": the scene covers the image";
    for (const std::string& isa : available_isas()) {
        ASSERT_TRUE(select_isa(isa));
        for (int tile : {8, 16, 64}) {
            const std::vector<Rgba8> out = render(mesh, {.threads = 2, .tile_size = tile}, shader);
            EXPECT_TRUE(out == reference) << name << " on " << isa << ", tile " << tile << ": "
                                          << facet_test::first_difference(out, reference, k_width);
        }
    }
}

template <class S>
void expect_every_isa_matches_the_specification(const char* name, float shininess = 40.0f,
                                                Lights lights = Lights::ordinary) {
    expect_every_isa_draws_what_scalar_draws<S>(name, [&](const Mesh& mesh) {
        return S{MeshArrays::of(mesh), uniforms(k_width, k_height, shininess, lights)};
    });
}

TEST(CompiledVisiblePass, LambertMatchesTheSpecificationOnEveryIsa) {
    expect_every_isa_matches_the_specification<shaders::Lambert>("Lambert");
    expect_every_isa_matches_the_specification<shaders::Lambert>("Lambert, NaN fill light", 40.0f, Lights::nan_fill);
    expect_every_isa_matches_the_specification<shaders::Lambert>("Lambert, grey lights", 40.0f, Lights::grey);
}
TEST(CompiledVisiblePass, BlinnPhongMatchesTheSpecificationOnEveryIsa) {
    // Every branch of portable_pow: x^0, moderate, and exponents that underflow and overflow.
    for (float shininess : {40.0f, 0.0f, 0.5f, 3000.0f, -2.0f})
        expect_every_isa_matches_the_specification<shaders::BlinnPhong>("BlinnPhong", shininess);
}
TEST(CompiledVisiblePass, BaseColourVariantsMatchTheSpecificationOnEveryIsa) {
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour");
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour, grey", 40.0f, Lights::grey);
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour, grey, NaN fill light",
                                                                           40.0f, Lights::grey_nan_fill);
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour, grey, huge fill light",
                                                                           40.0f, Lights::grey_huge_fill);
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour, grey, dim key light",
                                                                           40.0f, Lights::grey_dim_key);
    expect_every_isa_matches_the_specification<shaders::LambertBaseColour>("LambertBaseColour, grey, bright", 40.0f,
                                                                           Lights::grey_bright);
    expect_every_isa_matches_the_specification<shaders::BlinnPhongBaseColour>("BlinnPhongBaseColour");
}
TEST(CompiledVisiblePass, NormalsMatchesTheSpecificationOnEveryIsa) {
    expect_every_isa_matches_the_specification<shaders::Normals>("Normals");
}
TEST(CompiledVisiblePass, VertexColourMatchesTheSpecificationOnEveryIsa) {
    expect_every_isa_matches_the_specification<shaders::VertexColour>("VertexColour");
}
TEST(CompiledVisiblePass, FlatMatchesTheSpecificationOnEveryIsa) {
    expect_every_isa_matches_the_specification<shaders::Flat>("Flat");
}

// The grey Lambert kernel (the lambert mode's) where a byte is most easily wrong: normals aimed so
// that the specification's value lies within an ulp or two of where its byte changes, which random
// normals almost never are (a shortcut that approximates normalize and checks its own error bound
// too loosely passed LambertBaseColour's random cases above and failed here; docs/BENCHMARKS.md
// "Small meshes, session 10"). The image is a grid of squares of 4x4 pixels (whole blocks), each
// square's vertices sharing one normal: pairs of normals one float apart on either side of each
// byte's edge, and every third square an ordinary one.
std::vector<Vec3> normals_at_byte_edges(const ShadingUniforms& u) {
    auto byte = [&](float t) {
        const Vec3 n{t, 1.0f - t, 0.25f};
        return to_rgba8(shaders::detail::shade(u.base_colour, shaders::detail::lambert_term(normalize(n), u))).r;
    };
    std::vector<Vec3> out;
    constexpr int k_steps = 2048;
    for (int i = 0; i < k_steps; ++i) {
        float lo = -3.0f + 6.0f * static_cast<float>(i) / k_steps, hi = -3.0f + 6.0f * static_cast<float>(i + 1) / k_steps;
        if (byte(lo) == byte(hi)) continue;
        while (std::nextafter(lo, hi) != hi) {  // bisection down to two neighbouring floats
            const float mid = lo + (hi - lo) / 2;
            if (mid == lo || mid == hi) break;
            (byte(mid) == byte(lo) ? lo : hi) = mid;
        }
        out.push_back({lo, 1.0f - lo, 0.25f});
        out.push_back({hi, 1.0f - hi, 0.25f});
    }
    return out;
}

TEST(CompiledVisiblePass, LambertMatchesTheSpecificationAtByteEdges) {
    constexpr int k_size = 128, k_squares = k_size / 4;
    struct Case {
        const char* name;
        float key, base;
    } cases[] = {{"white key", 1.0f, 0.8f}, {"dim key", 0.5f, 0.8f}, {"bright key, clamped", 1.2f, 0.95f}};
    for (const Case& c : cases) {
        ShadingUniforms u;  // positions are clip coordinates
        u.key = {normalize(Vec3{0.3f, 0.8f, 0.6f}), {c.key, c.key, c.key}};
        u.fill = {{0, 0, 1}, {0, 0, 0}};
        u.base_colour = {c.base, c.base, c.base, 1.0f};
        const std::vector<Vec3> edges = normals_at_byte_edges(u);
        ASSERT_GE(edges.size(), 200u) << c.name << ": byte edges found";
        Mesh mesh;
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> any(-1.0f, 1.0f);
        for (int sq = 0; sq < k_squares * k_squares; ++sq) {
            const float x = -1.0f + 2.0f * static_cast<float>(sq % k_squares) / k_squares, y = -1.0f + 2.0f * static_cast<float>(sq / k_squares) / k_squares;
            const float side = 2.0f / k_squares;
            const Vec3 n = sq % 3 == 2 ? Vec3{any(rng), any(rng), any(rng)} : edges[static_cast<std::size_t>(sq) % edges.size()];
            const auto first = static_cast<std::uint32_t>(mesh.positions.size());
            for (const Vec3 p : {Vec3{x, y, 0.5f}, Vec3{x + side, y, 0.5f}, Vec3{x + side, y + side, 0.5f}, Vec3{x, y + side, 0.5f}}) {
                mesh.positions.push_back(p);
                mesh.normals.push_back(n);
            }
            for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(first + i);
        }
        const shaders::LambertBaseColour shader{MeshArrays::of(mesh), u};
        auto draw = [&](int threads, int tile) {
            Renderer renderer({.threads = threads, .tile_size = tile});
            Framebuffer fb(k_size, k_size);
            fb.clear(Vec4{0, 0, 0, 1}, 1.0f);
            DrawState state;
            state.cull = CullMode::none;
            renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices}, shader);
            return std::vector<Rgba8>(fb.colour_data(), fb.colour_data() + k_size * k_size);
        };
        facet_test::IsaGuard guard;
        ASSERT_TRUE(select_isa("scalar"));
        const std::vector<Rgba8> reference = draw(1, 64);
        std::size_t drawn = 0;  // the squares cover the image (no pixel is lit below the ambient's 30)
        for (const Rgba8 p : reference) drawn += p.r > 0;
        EXPECT_EQ(drawn, static_cast<std::size_t>(k_size * k_size)) << c.name;
        for (const std::string& isa : available_isas()) {
            if (isa == "scalar") continue;
            ASSERT_TRUE(select_isa(isa));
            for (int tile : {16, 64}) {
                const std::vector<Rgba8> out = draw(2, tile);
                EXPECT_TRUE(out == reference) << c.name << " on " << isa << ", tile " << tile << ": "
                                              << facet_test::first_difference(out, reference, k_size);
            }
        }
    }
}

// The lit mode's maps: small textures with every texel value's range, alpha included.
std::shared_ptr<const Texture> pattern(std::uint8_t seed) {
    Image img{13, 9, std::vector<Rgba8>(13 * 9)};
    for (int i = 0; i < 13 * 9; ++i)
        img.pixels[static_cast<std::size_t>(i)] = {static_cast<std::uint8_t>(i * 37 + seed), static_cast<std::uint8_t>(i * 91 + seed * 3),
                                                   static_cast<std::uint8_t>(i * 53 + 255 - seed), static_cast<std::uint8_t>(i * 7)};
    return std::make_shared<const Texture>(std::move(img));
}

struct LitCase {
    const char* name;
    ToneMapping tone_mapping;
    bool maps, unlit;
    float exposure, metallic, roughness;
    bool grey = false;  // grey base colours (most vertices) and emission: the kernel's one-channel path
};

template <class S>
void expect_lit_mode_matches_the_specification() {
    const std::shared_ptr<const Texture> textures[5] = {pattern(1), pattern(50), pattern(100), pattern(150), pattern(200)};
    UvTransform turned;
    const float m[6] = {0.8f, 0.6f, 0.25f, -0.6f, 0.8f, -1.5f};
    std::copy(m, m + 6, turned.m);
    for (const LitCase& c : {LitCase{"neutral, every map", ToneMapping::neutral, true, false, 1.0f, 1.0f, 1.0f},
                             LitCase{"aces, factors", ToneMapping::aces, false, false, 2.5f, 0.3f, 0.45f},
                             LitCase{"linear, every map, bright", ToneMapping::linear, true, false, 8.0f, 0.0f, 0.0f},
                             LitCase{"unlit", ToneMapping::neutral, true, true, 1.0f, 0.5f, 0.5f},
                             LitCase{"neutral, grey", ToneMapping::neutral, false, false, 1.5f, 0.2f, 0.35f, true}}) {
        Mesh grey;  // outlives the draws that read its arrays
        expect_every_isa_draws_what_scalar_draws<S>(c.name, [&](const Mesh& mesh) {
            if (c.grey) {
                // Grey vertex colours but every 7th: vectors of grey pixels, of others and mixed ones.
                grey = mesh;
                for (std::size_t i = 0; i < grey.colours.size(); ++i)
                    if (i % 7 != 0) grey.colours[i] = {grey.colours[i].x, grey.colours[i].x, grey.colours[i].x, grey.colours[i].w};
            }
            PbrUniforms p;
            p.environment = Environment::studio().get();
            p.tone_mapping = c.tone_mapping;
            p.exposure = c.exposure;
            p.unlit = c.unlit;
            p.metallic = c.metallic;
            p.roughness = c.roughness;
            p.emissive = {0.3f, 0.1f, 0.0f};
            p.normal_scale = 1.5f;
            p.occlusion_strength = 0.7f;
            if (c.maps) {
                MapBinding* maps[5] = {&p.base_colour, &p.metallic_roughness, &p.normal, &p.occlusion, &p.emissive_map};
                for (int i = 0; i < 5; ++i) maps[i]->texture = textures[i].get();
                p.normal.sampler = {Wrap::mirror, Wrap::clamp, Filter::trilinear};
                p.emissive_map.sampler.filter = Filter::bilinear;
                if (c.exposure > 1) {
                    // The other samplers: the kernel samples bilinear and trilinear maps in lanes,
                    // the others (nearest, transformed) lane by lane with the scalar sampler.
                    p.metallic_roughness.sampler = {Wrap::clamp, Wrap::mirror, Filter::bilinear};
                    p.occlusion.sampler = {Wrap::repeat, Wrap::repeat, Filter::nearest};
                    p.emissive_map.sampler = {Wrap::mirror, Wrap::repeat, Filter::trilinear};
                } else {
                    p.base_colour.transform = turned;
                    p.base_colour.transformed = true;
                }
            }
            if (c.grey) p.emissive = {0.2f, 0.2f, 0.2f};
            return S{MeshArrays::of(c.grey ? grey : mesh), uniforms(k_width, k_height, 40.0f, c.grey ? Lights::grey : Lights::ordinary), p};
        });
    }
}

TEST(CompiledVisiblePass, PbrMatchesTheSpecificationOnEveryIsa) { expect_lit_mode_matches_the_specification<shaders::Pbr>(); }
TEST(CompiledVisiblePass, PbrNormalMappedMatchesTheSpecificationOnEveryIsa) {
    expect_lit_mode_matches_the_specification<shaders::PbrNormalMapped>();
}

// A type derived from a built-in shader is a different shader, drawn by the generic path.
static_assert(!detail::CompiledVisiblePass<Wrapped<shaders::Lambert>>::available);
static_assert(!detail::CompiledVisiblePass<EveryFragment<shaders::Lambert>>::available);
static_assert(!detail::CompiledVisiblePass<shaders::Textured>::available);

}  // namespace
