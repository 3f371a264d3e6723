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
#include <array>
#include <cmath>
#include <type_traits>

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

// The varyings of the built-in shaders, each a mesh attribute as vertex() computes it:
//   uv        the texture coordinates (2 floats; 0, 0 without them)
//   normal    the world-space normal, u.normal_to_world * n, not normalized (3; 0 without normals)
//   position  the world-space position, u.model * p (3)
//   colour    the vertex colour times u.base_colour, or u.base_colour without colours (4)
enum class Varying { uv, normal, position, colour };

constexpr int varying_width(Varying v) { return v == Varying::uv ? 2 : v == Varying::colour ? 4 : 3; }

// A built-in shader's varyings, declared once and in order, each starting where the one before it
// ends: the shader's vertex() writes them (VaryingLayout::vertex), its fragment() reads them (of),
// and its compiled vertex stage and SIMD shading kernels find each at at(): no slot is numbered by
// hand. Adding a built-in shader is its layout, its fragment() and, if it has them, its kernels.
template <Varying... V>
struct VaryingLayout {
    static constexpr int count = (0 + ... + varying_width(V));
    // The first float of varying v, or -1 when the shader has none.
    static constexpr int at(Varying v) {
        int first = 0;
        for (Varying w : std::array<Varying, sizeof...(V)>{V...}) {
            if (w == v) return first;
            first += varying_width(w);
        }
        return -1;
    }
    static constexpr bool has(Varying v) { return at(v) >= 0; }
    // The floats from the first up to the end of v: a k_derivative_count that covers v.
    static constexpr int through(Varying v) { return at(v) + varying_width(v); }
    static constexpr int listed(Varying v) { return (0 + ... + (V == v ? 1 : 0)); }
    static_assert(((listed(V) == 1) && ...), "each varying is listed once");

    // Varying v of `in` (the interpolated values, or their ddx or ddy): a Vec2, Vec3 or Vec4.
    template <Varying v>
    static auto of(const Varyings<count>& in) {
        static_assert(has(v), "the shader has no such varying");
        if constexpr (varying_width(v) == 2) return in.vec2(at(v));
        else if constexpr (varying_width(v) == 3) return in.vec3(at(v));
        else return in.vec4(at(v));
    }

    // Every built-in shader's vertex(): the varyings of mesh vertex i into `out`, and its clip position.
    static Vec4 vertex(const MeshArrays& mesh, const ShadingUniforms& u, std::uint32_t i, Varyings<count>& out) {
        if constexpr (has(Varying::uv)) out.set(at(Varying::uv), detail::uv_of(mesh, i));
        if constexpr (has(Varying::normal)) out.set(at(Varying::normal), detail::world_normal(mesh, u, i));
        if constexpr (has(Varying::position))
            out.set(at(Varying::position), transform_point(u.model, mesh.positions[i]));
        if constexpr (has(Varying::colour)) out.set(at(Varying::colour), detail::vertex_colour(mesh, u, i));
        return u.clip_from_object * Vec4(mesh.positions[i], 1);
    }
};

struct VertexColour {
    using Layout = VaryingLayout<Varying::colour>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const { return Layout::of<Varying::colour>(in.v); }
};

struct Flat {
    using Layout = VaryingLayout<Varying::position, Varying::colour>;
    static constexpr int k_varyings = Layout::count;
    static constexpr int k_derivative_count = Layout::through(Varying::position);  // its colour needs none
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        // The face normal is perpendicular to both screen derivatives of the position; turn it
        // toward the eye so both sides of a face are lit the same.
        const Vec3 position = Layout::of<Varying::position>(in.v);
        Vec3 n = normalize(cross(Layout::of<Varying::position>(in.ddx), Layout::of<Varying::position>(in.ddy)));
        if (dot(n, u.eye - position) < 0) n = -n;
        return detail::shade(Layout::of<Varying::colour>(in.v), detail::lambert_term(n, u));
    }
};

// Where a lit shader's albedo comes from: the mesh's vertex colours (interpolated) times
// u.base_colour, or u.base_colour alone for the whole mesh. The second needs four varyings fewer,
// which is less to interpolate per pixel and to copy per triangle.
enum class Albedo { vertex_colours, base_colour };

template <Albedo A>
struct LambertShader {
    static constexpr bool k_vertex_colours = A == Albedo::vertex_colours;
    using Layout = std::conditional_t<k_vertex_colours, VaryingLayout<Varying::normal, Varying::colour>,
                                      VaryingLayout<Varying::normal>>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        const Vec3 n = normalize(Layout::template of<Varying::normal>(in.v));
        return detail::shade(albedo(in), detail::lambert_term(n, u));
    }
    Vec4 albedo(const FragmentIn<k_varyings>& in) const {
        if constexpr (k_vertex_colours) return Layout::template of<Varying::colour>(in.v);
        else return u.base_colour;
    }
};
using Lambert = LambertShader<Albedo::vertex_colours>;
using LambertBaseColour = LambertShader<Albedo::base_colour>;

template <Albedo A>
struct BlinnPhongShader {
    static constexpr bool k_vertex_colours = A == Albedo::vertex_colours;
    using Layout = std::conditional_t<k_vertex_colours,
                                      VaryingLayout<Varying::normal, Varying::position, Varying::colour>,
                                      VaryingLayout<Varying::normal, Varying::position>>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        Vec3 n = normalize(Layout::template of<Varying::normal>(in.v));
        if (!in.front_facing) n = -n;  // two-sided: the inside of an open surface is lit too
        const Vec3 to_eye = normalize(u.eye - Layout::template of<Varying::position>(in.v));
        return detail::blinn_phong(n, to_eye, albedo(in), u);
    }
    Vec4 albedo(const FragmentIn<k_varyings>& in) const {
        if constexpr (k_vertex_colours) return Layout::template of<Varying::colour>(in.v);
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
    using Layout = VaryingLayout<Varying::uv, Varying::normal, Varying::position, Varying::colour>;
    static constexpr int k_varyings = Layout::count;
    static constexpr int k_derivative_count = Layout::through(Varying::uv);  // for mip selection
    MeshArrays mesh;
    ShadingUniforms u;
    TextureBinding tex;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    auto fragment(const FragmentIn<k_varyings>& in) const {
        const Vec4 albedo = detail::albedo(tex, in, Layout::at(Varying::uv), Layout::of<Varying::colour>(in.v));
        if constexpr (AlphaCutoff) {
            if (albedo.w < tex.alpha_cutoff) return std::optional<Vec4>{};
            return std::optional<Vec4>{lit(in, albedo)};
        } else {
            return lit(in, albedo);
        }
    }
    Vec4 lit(const FragmentIn<k_varyings>& in, Vec4 albedo) const {
        Vec3 n = normalize(Layout::of<Varying::normal>(in.v));
        if (!in.front_facing) n = -n;
        return detail::blinn_phong(n, normalize(u.eye - Layout::of<Varying::position>(in.v)), albedo, u);
    }
};
using Textured = TexturedShader<true>;
using TexturedOpaque = TexturedShader<false>;

template <bool AlphaCutoff>
struct TextureUnlitShader {
    using Layout = VaryingLayout<Varying::uv, Varying::colour>;
    static constexpr int k_varyings = Layout::count;
    static constexpr int k_derivative_count = Layout::through(Varying::uv);
    MeshArrays mesh;
    ShadingUniforms u;
    TextureBinding tex;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    auto fragment(const FragmentIn<k_varyings>& in) const {
        const Vec4 albedo = detail::albedo(tex, in, Layout::at(Varying::uv), Layout::of<Varying::colour>(in.v));
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
    using Layout = VaryingLayout<Varying::normal>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        const Vec3 n = normalize(Layout::of<Varying::normal>(in.v));
        return {0.5f + 0.5f * n.x, 0.5f + 0.5f * n.y, 0.5f + 0.5f * n.z, 1};
    }
};

struct Mask {
    using Layout = VaryingLayout<>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>&) const { return {1, 1, 1, 1}; }
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
template <class Layout>
void run_vertex_stage(const MeshArrays& mesh, const ShadingUniforms& u, std::size_t begin, std::size_t end,
                      Vec4* clip, float* varyings) {
    using shaders::Varying;
    static_assert(Layout::count == (Layout::has(Varying::normal) ? 3 : 0) + (Layout::has(Varying::colour) ? 4 : 0),
                  "the compiled vertex stage computes the normal and the colour, nothing else");
    constexpr int N = Layout::count, normal_at = Layout::at(Varying::normal), colour_at = Layout::at(Varying::colour);
    const std::size_t n = end - begin;
    transform_points(u.clip_from_object, mesh.positions + begin, n, clip);
    if constexpr (normal_at >= 0)
        transform_directions(u.normal_to_world, mesh.normals ? mesh.normals + begin : nullptr, n,
                             varyings + normal_at, N);
    if constexpr (colour_at >= 0)
        for (std::size_t j = 0; j < n; ++j) {
            const Vec4 c = shaders::detail::vertex_colour(mesh, u, static_cast<std::uint32_t>(begin + j));
            for (int k = 0; k < 4; ++k) varyings[j * N + static_cast<std::size_t>(colour_at + k)] = c[static_cast<std::size_t>(k)];
        }
}
#define FACET_COMPILED_VERTEX_STAGE(S)                                                               \
    template <>                                                                                     \
    struct CompiledVertexStage<shaders::S> {                                                        \
        static constexpr bool available = true;                                                     \
        static void run(const shaders::S& s, std::size_t begin, std::size_t end, Vec4* clip, float* varyings) { \
            run_vertex_stage<shaders::S::Layout>(s.mesh, s.u, begin, end, clip, varyings);          \
        }                                                                                           \
    };
FACET_COMPILED_VERTEX_STAGE(Lambert)
FACET_COMPILED_VERTEX_STAGE(LambertBaseColour)
FACET_COMPILED_VERTEX_STAGE(Normals)
FACET_COMPILED_VERTEX_STAGE(VertexColour)
FACET_COMPILED_VERTEX_STAGE(Mask)
#undef FACET_COMPILED_VERTEX_STAGE
}  // namespace detail
}  // namespace facet
FACET_API_END
