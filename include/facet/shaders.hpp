// facet: built-in shaders for meshes, all plain types satisfying facet::Shader (inlined, no
// virtual calls). They read a mesh's arrays by index and share one ShadingUniforms block.
//   VertexColour  unlit, Gouraud-interpolated vertex colours
//   Flat          one normal per face, from the screen derivatives of the world position
//   Lambert       per-pixel diffuse from one directional light plus ambient
//   BlinnPhong    per-pixel key + fill lights, ambient and specular highlights, two-sided
//                 (both also as ...BaseColour: one colour for the whole mesh, fewer varyings)
//   Normals       world-space normal as colour (0.5 + 0.5 n)
//   Mask          unlit white
//   Textured      BlinnPhong with the material's base-colour texture and alpha (mask / blend)
//   TextureUnlit  the base-colour texture and material colour, no lighting
//                 (both also as ...Opaque: no alpha cutoff, so they never discard and the renderer
//                 shades visible pixels only; the same colours when tex.alpha_cutoff < 0)
#pragma once

#include <algorithm>
#include <cmath>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/detail/vertex_stage.hpp"
#include "facet/detail/visible_pass.hpp"
#include "facet/math/portable_pow.hpp"
#include "facet/mesh.hpp"
#include "facet/pipeline.hpp"
#include "facet/texture.hpp"

FACET_API_BEGIN
namespace facet {

struct DirectionalLight {
    Vec3 direction{0, 0, 1};  // world space, pointing toward the light; normalized by the shaders' user
    Vec3 colour{1, 1, 1};
};

struct ShadingUniforms {
    Mat4 model;              // object -> world
    Mat4 clip_from_object;   // projection * view * model
    Mat3 normal_to_world;    // normal_matrix(model)
    Vec3 eye;                // world-space camera position (specular, two-sided flat normals)
    Vec4 base_colour{1, 1, 1, 1};  // multiplies the vertex colours
    DirectionalLight key;
    DirectionalLight fill{{0, 0, 1}, {0, 0, 0}};
    // Lambert's terms without a highlight (facet/defaults.hpp); render_scene sets its Lighting's.
    float ambient = defaults::k_lambert_ambient;
    float diffuse = defaults::k_lambert_diffuse;
    float specular = 0.0f;   // strength of the Blinn-Phong highlight
    float shininess = defaults::k_uniform_shininess;
};

// Read-only view of the mesh arrays a shader needs (normals and colours may be absent).
struct MeshArrays {
    const Vec3* positions = nullptr;
    const Vec3* normals = nullptr;
    const Vec4* colours = nullptr;
    const Vec2* uvs = nullptr;
    static MeshArrays of(const Mesh& m) {
        return {m.positions.data(), m.normals.empty() ? nullptr : m.normals.data(),
                m.colours.empty() ? nullptr : m.colours.data(), m.uvs.empty() ? nullptr : m.uvs.data()};
    }
};

// A material's texture and how its alpha is used, for the textured shaders.
struct TextureBinding {
    const Texture* texture = nullptr;  // null: the material colour alone
    Sampler sampler;
    float alpha_cutoff = -1;           // discard below this alpha; negative: never
};

namespace shaders {

namespace detail {
inline Vec4 vertex_colour(const MeshArrays& m, const ShadingUniforms& u, std::uint32_t i) {
    return m.colours ? u.base_colour * m.colours[i] : u.base_colour;
}
inline Vec3 world_normal(const MeshArrays& m, const ShadingUniforms& u, std::uint32_t i) {
    return m.normals ? u.normal_to_world * m.normals[i] : Vec3{};
}
[[gnu::always_inline]] inline Vec3 lambert_term(Vec3 n, const ShadingUniforms& u) {
    const float k = std::max(dot(n, u.key.direction), 0.0f), f = std::max(dot(n, u.fill.direction), 0.0f);
    return Vec3{u.ambient, u.ambient, u.ambient} + (u.key.colour * k + u.fill.colour * f) * u.diffuse;
}
inline Vec4 shade(Vec4 albedo, Vec3 light) { return {albedo.x * light.x, albedo.y * light.y, albedo.z * light.z, albedo.w}; }
inline Vec2 uv_of(const MeshArrays& m, std::uint32_t i) { return m.uvs ? m.uvs[i] : Vec2{}; }
// Base colour at a pixel: material x vertex colour (in `colour`) x texture sampled at uv.
template <int N>
inline Vec4 albedo(const TextureBinding& t, const FragmentIn<N>& in, int uv_at, Vec4 colour) {
    if (!t.texture) return colour;
    return colour * t.texture->sample(in.v.vec2(uv_at), in.ddx.vec2(uv_at), in.ddy.vec2(uv_at), t.sampler);
}
inline Vec4 blinn_phong(Vec3 n, Vec3 to_eye, Vec4 albedo, const ShadingUniforms& u) {
    Vec4 c = shade(albedo, lambert_term(n, u));
    const Vec3 h = normalize(u.key.direction + to_eye);
    const float s = u.specular * portable_pow(std::max(dot(n, h), 0.0f), u.shininess);
    return {c.x + s * u.key.colour.x, c.y + s * u.key.colour.y, c.z + s * u.key.colour.z, c.w};
}
}  // namespace detail

struct VertexColour {
    static constexpr int k_varyings = 4;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<4>& out) const {
        out.set(0, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    Vec4 fragment(const FragmentIn<4>& in) const { return in.v.vec4(0); }
};

struct Flat {
    static constexpr int k_varyings = 7;  // world position, colour
    static constexpr int k_derivative_count = 3;  // the position's: its colour needs none
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<7>& out) const {
        out.set(0, transform_point(u.model, mesh.positions[i]));
        out.set(3, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    Vec4 fragment(const FragmentIn<7>& in) const {
        // The face normal is perpendicular to both screen derivatives of the position; turn it
        // toward the eye so both sides of a face are lit the same.
        Vec3 n = normalize(cross(in.ddx.vec3(0), in.ddy.vec3(0)));
        if (dot(n, u.eye - in.v.vec3(0)) < 0) n = -n;
        return detail::shade(in.v.vec4(3), detail::lambert_term(n, u));
    }
};

// Where a lit shader's albedo comes from: the mesh's vertex colours (interpolated) times
// u.base_colour, or u.base_colour alone for the whole mesh. The second needs four varyings fewer,
// which is less to interpolate per pixel and to copy per triangle.
enum class Albedo { vertex_colours, base_colour };

template <Albedo A>
struct LambertShader {
    static constexpr bool k_vertex_colours = A == Albedo::vertex_colours;
    static constexpr int k_varyings = k_vertex_colours ? 7 : 3;  // normal, colour
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const {
        out.set(0, detail::world_normal(mesh, u, i));
        if constexpr (k_vertex_colours) out.set(3, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        return detail::shade(albedo(in), detail::lambert_term(normalize(in.v.vec3(0)), u));
    }
    Vec4 albedo(const FragmentIn<k_varyings>& in) const {
        if constexpr (k_vertex_colours) return in.v.vec4(3);
        else return u.base_colour;
    }
};
using Lambert = LambertShader<Albedo::vertex_colours>;
using LambertBaseColour = LambertShader<Albedo::base_colour>;

template <Albedo A>
struct BlinnPhongShader {
    static constexpr bool k_vertex_colours = A == Albedo::vertex_colours;
    static constexpr int k_varyings = k_vertex_colours ? 10 : 6;  // normal, world position, colour
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const {
        out.set(0, detail::world_normal(mesh, u, i));
        out.set(3, transform_point(u.model, mesh.positions[i]));
        if constexpr (k_vertex_colours) out.set(6, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        Vec3 n = normalize(in.v.vec3(0));
        if (!in.front_facing) n = -n;  // two-sided: the inside of an open surface is lit too
        return detail::blinn_phong(n, normalize(u.eye - in.v.vec3(3)), albedo(in), u);
    }
    Vec4 albedo(const FragmentIn<k_varyings>& in) const {
        if constexpr (k_vertex_colours) return in.v.vec4(6);
        else return u.base_colour;
    }
};
using BlinnPhong = BlinnPhongShader<Albedo::vertex_colours>;
using BlinnPhongBaseColour = BlinnPhongShader<Albedo::base_colour>;

// With AlphaCutoff, a pixel whose albedo alpha is below tex.alpha_cutoff is discarded (a material's
// AlphaMode::mask). Without, nothing is: a shader that cannot discard is drawn visible-only (depth
// first, then fragment() once per visible pixel, detail/fragment.hpp), which spares the texture lookups
// and lighting of every pixel drawn over later.
template <bool AlphaCutoff>
struct TexturedShader {
    static constexpr int k_varyings = 12;  // uv, normal, world position, colour
    static constexpr int k_derivative_count = 2;  // the uv pair, for mip selection
    MeshArrays mesh;
    ShadingUniforms u;
    TextureBinding tex;
    Vec4 vertex(std::uint32_t i, Varyings<12>& out) const {
        out.set(0, detail::uv_of(mesh, i));
        out.set(2, detail::world_normal(mesh, u, i));
        out.set(5, transform_point(u.model, mesh.positions[i]));
        out.set(8, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    auto fragment(const FragmentIn<12>& in) const {
        const Vec4 albedo = detail::albedo(tex, in, 0, in.v.vec4(8));
        if constexpr (AlphaCutoff) {
            if (albedo.w < tex.alpha_cutoff) return std::optional<Vec4>{};
            return std::optional<Vec4>{lit(in, albedo)};
        } else {
            return lit(in, albedo);
        }
    }
    Vec4 lit(const FragmentIn<12>& in, Vec4 albedo) const {
        Vec3 n = normalize(in.v.vec3(2));
        if (!in.front_facing) n = -n;
        return detail::blinn_phong(n, normalize(u.eye - in.v.vec3(5)), albedo, u);
    }
};
using Textured = TexturedShader<true>;
using TexturedOpaque = TexturedShader<false>;

template <bool AlphaCutoff>
struct TextureUnlitShader {
    static constexpr int k_varyings = 6;  // uv, colour
    static constexpr int k_derivative_count = 2;
    MeshArrays mesh;
    ShadingUniforms u;
    TextureBinding tex;
    Vec4 vertex(std::uint32_t i, Varyings<6>& out) const {
        out.set(0, detail::uv_of(mesh, i));
        out.set(2, detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    auto fragment(const FragmentIn<6>& in) const {
        const Vec4 albedo = detail::albedo(tex, in, 0, in.v.vec4(2));
        if constexpr (AlphaCutoff) {
            if (albedo.w < tex.alpha_cutoff) return std::optional<Vec4>{};
            return std::optional<Vec4>{albedo};
        } else {
            return albedo;
        }
    }
};
using TextureUnlit = TextureUnlitShader<true>;
using TextureUnlitOpaque = TextureUnlitShader<false>;

struct Normals {
    static constexpr int k_varyings = 3;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<3>& out) const {
        out.set(0, detail::world_normal(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
    Vec4 fragment(const FragmentIn<3>& in) const {
        const Vec3 n = normalize(in.v.vec3(0));
        return {0.5f + 0.5f * n.x, 0.5f + 0.5f * n.y, 0.5f + 0.5f * n.z, 1};
    }
};

struct Mask {
    static constexpr int k_varyings = 0;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<0>&) const { return u.clip_from_object * Vec4(mesh.positions[i], 1); }
    Vec4 fragment(const FragmentIn<0>&) const { return {1, 1, 1, 1}; }
};

}  // namespace shaders

// The built-in shaders whose visible pixels are shaded by SIMD kernels (src/shade/visible_simd*):
// the same bytes as fragment(), several pixels at a time. "scalar" (facet/isa.hpp) runs fragment().
namespace detail {
#define FACET_COMPILED_VISIBLE_PASS(S)                                                                  \
    template <>                                                                                     \
    struct CompiledVisiblePass<shaders::S> {                                                        \
        static constexpr bool available = true;                                                     \
        static void run(const shaders::S& shader, const VisibleTile& tile, TargetView colour);          \
    };
FACET_COMPILED_VISIBLE_PASS(Lambert)
FACET_COMPILED_VISIBLE_PASS(LambertBaseColour)
FACET_COMPILED_VISIBLE_PASS(BlinnPhong)
FACET_COMPILED_VISIBLE_PASS(BlinnPhongBaseColour)
FACET_COMPILED_VISIBLE_PASS(Normals)
FACET_COMPILED_VISIBLE_PASS(VertexColour)
FACET_COMPILED_VISIBLE_PASS(Flat)
#undef FACET_COMPILED_VISIBLE_PASS

// The built-in shaders whose vertex() is the clip position plus the world normal and/or the vertex
// colour: their vertex stage in SIMD (src/vertex/transform_simd.cpp), the same bytes as vertex().
// Vertices [begin, end): clip[j] and varyings[j * N ..] belong to vertex begin + j.
template <int N, int NormalAt, int ColourAt>  // where each varying starts; -1: the shader has none
void run_vertex_stage(const MeshArrays& mesh, const ShadingUniforms& u, std::size_t begin, std::size_t end,
                      Vec4* clip, float* varyings) {
    const std::size_t n = end - begin;
    transform_points(u.clip_from_object, mesh.positions + begin, n, clip);
    if constexpr (NormalAt >= 0)
        transform_directions(u.normal_to_world, mesh.normals ? mesh.normals + begin : nullptr, n,
                             varyings + NormalAt, N);
    if constexpr (ColourAt >= 0)
        for (std::size_t j = 0; j < n; ++j) {
            const Vec4 c = shaders::detail::vertex_colour(mesh, u, static_cast<std::uint32_t>(begin + j));
            for (int k = 0; k < 4; ++k) varyings[j * N + static_cast<std::size_t>(ColourAt + k)] = c[static_cast<std::size_t>(k)];
        }
}
#define FACET_COMPILED_VERTEX_STAGE(S, NormalAt, ColourAt)                                           \
    template <>                                                                                     \
    struct CompiledVertexStage<shaders::S> {                                                        \
        static constexpr bool available = true;                                                     \
        static void run(const shaders::S& s, std::size_t begin, std::size_t end, Vec4* clip, float* varyings) { \
            run_vertex_stage<shaders::S::k_varyings, NormalAt, ColourAt>(s.mesh, s.u, begin, end, clip, varyings); \
        }                                                                                           \
    };
FACET_COMPILED_VERTEX_STAGE(Lambert, 0, 3)
FACET_COMPILED_VERTEX_STAGE(LambertBaseColour, 0, -1)
FACET_COMPILED_VERTEX_STAGE(Normals, 0, -1)
FACET_COMPILED_VERTEX_STAGE(VertexColour, -1, 0)
FACET_COMPILED_VERTEX_STAGE(Mask, -1, -1)
#undef FACET_COMPILED_VERTEX_STAGE
}  // namespace detail
}  // namespace facet
FACET_API_END
