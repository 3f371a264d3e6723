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
//   Pbr           glTF's metallic-roughness under an environment light (the lit mode): base colour,
//                 metallic-roughness, occlusion and emissive maps, image-based lighting, exposure,
//                 tone mapping and sRGB encoding; PbrNormalMapped adds the tangent-space normal map
//                 (both also as ...Masked, which discard below the alpha cutoff); PbrUnlitBlended is
//                 its colour for alpha-blended unlit materials, with fewer varyings
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/detail/blend_pass.hpp"
#include "facet/detail/vertex_stage.hpp"
#include "facet/environment.hpp"
#include "facet/detail/visible_pass.hpp"
#include "facet/math/portable_pow.hpp"
#include "facet/mesh.hpp"
#include "facet/pipeline.hpp"
#include "facet/texture.hpp"
#include "facet/tone_mapping.hpp"

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
    // -1 when `model` mirrors (a negative determinant): tangents' bitangent side turns over with it.
    float handedness = 1.0f;
};

// Read-only view of the mesh arrays a shader needs (normals and colours may be absent).
struct MeshArrays {
    const Vec3* positions = nullptr;
    const Vec3* normals = nullptr;
    const Vec4* colours = nullptr;
    const Vec2* uvs = nullptr;
    const Vec4* tangents = nullptr;
    static MeshArrays of(const Mesh& m) {
        return {m.positions.data(), m.normals.empty() ? nullptr : m.normals.data(),
                m.colours.empty() ? nullptr : m.colours.data(), m.uvs.empty() ? nullptr : m.uvs.data(),
                m.tangents.empty() ? nullptr : m.tangents.data()};
    }
};

// A material's texture and how its alpha is used, for the textured shaders.
struct TextureBinding {
    const Texture* texture = nullptr;  // null: the material colour alone
    Sampler sampler;
    float alpha_cutoff = -1;           // discard below this alpha; negative: never
};

// A material's map as the lit shader samples it (uv transformed first when `transformed`).
struct MapBinding {
    const Texture* texture = nullptr;  // null: no map
    Sampler sampler;
    UvTransform transform;
    bool transformed = false;  // !transform.is_identity(), decided once per draw
};

// What shaders::Pbr reads besides ShadingUniforms: the material (glTF's metallic-roughness; the
// factors multiply the maps), the environment light and the display transform.
struct PbrUniforms {
    float metallic = defaults::k_metallic, roughness = defaults::k_roughness;
    float normal_scale = 1, occlusion_strength = 1;
    Vec3 emissive{};
    MapBinding base_colour, metallic_roughness, normal, occlusion, emissive_map;
    float alpha_cutoff = -1;  // the ...Masked shaders discard below it
    bool unlit = false;       // KHR_materials_unlit: the base colour as radiance
    const Environment* environment = nullptr;  // never null when drawn
    float exposure = 1;  // multiplies the radiance before tone mapping
    ToneMapping tone_mapping = ToneMapping::neutral;
};

namespace shaders {

namespace detail {
inline Vec4 vertex_colour(const MeshArrays& m, const ShadingUniforms& u, std::uint32_t i) {
    return m.colours ? u.base_colour * m.colours[i] : u.base_colour;
}
inline Vec3 world_normal(const MeshArrays& m, const ShadingUniforms& u, std::uint32_t i) {
    return m.normals ? u.normal_to_world * m.normals[i] : Vec3{};
}
inline Vec4 world_tangent(const MeshArrays& m, const ShadingUniforms& u, std::uint32_t i) {
    if (!m.tangents) return {0, 0, 0, 1};
    const Vec4 t = m.tangents[i];
    return Vec4(u.model.upper3x3() * t.xyz(), t.w * u.handedness);
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
//   tangent   the world-space tangent, u.model's 3x3 times t.xyz, and t.w * u.handedness (4;
//             0, 0, 0, 1 without tangents)
enum class Varying { uv, normal, position, colour, tangent };

constexpr int varying_width(Varying v) {
    return v == Varying::uv ? 2 : v == Varying::colour || v == Varying::tangent ? 4 : 3;
}

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
        if constexpr (has(Varying::tangent)) out.set(at(Varying::tangent), detail::world_tangent(mesh, u, i));
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

namespace detail {
// A map's texel for the pixel: uv and its screen derivatives through the map's transform.
[[gnu::always_inline]] inline Vec4 sample_map(const MapBinding& m, Vec2 uv, Vec2 ddx, Vec2 ddy) {
    if (m.transformed) uv = m.transform.apply(uv), ddx = m.transform.apply_linear(ddx), ddy = m.transform.apply_linear(ddy);
    return m.texture->sample(uv, ddx, ddy, m.sampler);
}

// The split-sum image-based lighting of glTF's BRDF with Fdez-Aguera's multiple-scattering terms,
// as the Khronos glTF Sample Viewer computes it: for base colour c, metallic m, roughness r, unit
// normal n and unit direction to the eye v, with n.v clamped to [0, 1]:
//   f0 = mix(0.04, c, m), c_diff = c (1 - m), (A, B) = split_sum(n.v, r)
//   Fr = max(1 - r, f0) - f0, k_S = f0 + Fr (1 - n.v)^5, FssEss = k_S A + B
//   Ems = 1 - (A + B), F_avg = f0 + (1 - f0) / 21, FmsEms = Ems FssEss F_avg / (1 - F_avg Ems)
//   specular = prefiltered(reflect(-v, n), r) FssEss
//   diffuse = (FmsEms + c_diff (1 - FssEss + FmsEms)) irradiance(n)
struct PbrSurface {
    Vec3 base_colour;
    float metallic, roughness;
};
inline Vec3 image_based_light(const PbrSurface& s, Vec3 n, Vec3 v, const Environment& env) {
    const float n_dot_v_raw = dot(n, v);
    const float n_dot_v = n_dot_v_raw > 0 ? (n_dot_v_raw < 1 ? n_dot_v_raw : 1) : 0;
    const Vec3 r = n * (2 * n_dot_v_raw) - v;
    const Vec2 ab = split_sum(n_dot_v, s.roughness);
    const Vec3 dielectric{0.04f, 0.04f, 0.04f};
    const Vec3 f0 = dielectric + (s.base_colour - dielectric) * s.metallic;
    const Vec3 c_diff = s.base_colour * (1 - s.metallic);
    const float x = 1 - n_dot_v, x5 = x * x * x * x * x;
    const float smooth = 1 - s.roughness;
    const Vec3 fr = max(Vec3{smooth, smooth, smooth}, f0) - f0;
    const Vec3 k_s = f0 + fr * x5;
    const Vec3 fss_ess = k_s * ab.x + Vec3{ab.y, ab.y, ab.y};
    const float ems = 1 - (ab.x + ab.y);
    const Vec3 f_avg = f0 + (Vec3{1, 1, 1} - f0) * (1 / 21.0f);
    const Vec3 fms_ems = fss_ess * f_avg * ems / (Vec3{1, 1, 1} - f_avg * ems);
    const Vec3 k_d = c_diff * (Vec3{1, 1, 1} - fss_ess + fms_ems);
    const Vec3 specular = env.specular(r, s.roughness * static_cast<float>(Environment::k_levels - 1)) * fss_ess;
    const Vec3 diffuse = (fms_ems + k_d) * env.diffuse(n);
    return diffuse + specular;
}

// Linear radiance to the display: exposure, tone mapping, the sRGB transfer function.
inline Vec3 display(Vec3 radiance, const PbrUniforms& p) {
    const Vec3 t = tone_map(radiance * p.exposure, p.tone_mapping);
    return {linear_to_srgb(t.x), linear_to_srgb(t.y), linear_to_srgb(t.z)};
}
}  // namespace detail

// glTF 2.0's metallic-roughness material lit by an environment (facet/environment.hpp), the lit
// mode. Per pixel: base colour = material colour x vertex colour x the base-colour map (sRGB
// decoded after filtering); metallic and roughness = factors x the map's B and G; the normal
// (turned toward the viewer on back faces, tangent frame included), perturbed by the normal map
// where NormalMap; image_based_light; times mix(1, occlusion map's R, strength); plus emissive x
// its map; then display(). Alpha: the base colour's. The texture coordinates' derivatives (for
// mip selection) are exact, as for the textured shaders.
template <bool NormalMap, bool AlphaCutoff>
struct PbrShader {
    using Layout = std::conditional_t<NormalMap,
                                      VaryingLayout<Varying::uv, Varying::normal, Varying::position, Varying::tangent, Varying::colour>,
                                      VaryingLayout<Varying::uv, Varying::normal, Varying::position, Varying::colour>>;
    static constexpr int k_varyings = Layout::count;
    static constexpr int k_derivative_count = Layout::through(Varying::uv);
    MeshArrays mesh;
    ShadingUniforms u;
    PbrUniforms pbr;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    auto fragment(const FragmentIn<k_varyings>& in) const {
        const Vec4 base = base_colour(in);
        if constexpr (AlphaCutoff) {
            if (base.w < pbr.alpha_cutoff) return std::optional<Vec4>{};
            return std::optional<Vec4>{lit(in, base)};
        } else {
            return lit(in, base);
        }
    }
    // Material colour x vertex colour (the colour varying), x the decoded base-colour map.
    Vec4 base_colour(const FragmentIn<k_varyings>& in) const {
        const Vec4 c = Layout::template of<Varying::colour>(in.v);
        if (!pbr.base_colour.texture) return c;
        const Vec4 t = sample(pbr.base_colour, in);
        return {c.x * srgb_to_linear(t.x), c.y * srgb_to_linear(t.y), c.z * srgb_to_linear(t.z), c.w * t.w};
    }
    Vec4 sample(const MapBinding& m, const FragmentIn<k_varyings>& in) const {
        constexpr int uv = Layout::at(Varying::uv);
        return detail::sample_map(m, in.v.vec2(uv), in.ddx.vec2(uv), in.ddy.vec2(uv));
    }
    Vec4 lit(const FragmentIn<k_varyings>& in, Vec4 base) const {
        if (pbr.unlit) return Vec4(detail::display(base.xyz(), pbr), base.w);
        detail::PbrSurface s{base.xyz(), pbr.metallic, pbr.roughness};
        if (pbr.metallic_roughness.texture) {
            const Vec4 t = sample(pbr.metallic_roughness, in);
            s.roughness = s.roughness * t.y;
            s.metallic = s.metallic * t.z;
        }
        const Vec3 n = normal(in);
        const Vec3 v = normalize(u.eye - Layout::template of<Varying::position>(in.v));
        Vec3 c = detail::image_based_light(s, n, v, *pbr.environment);
        if (pbr.occlusion.texture) {
            const float ao = 1 + pbr.occlusion_strength * (sample(pbr.occlusion, in).x - 1);
            c = c * ao;
        }
        Vec3 e = pbr.emissive;
        if (pbr.emissive_map.texture) {
            const Vec4 t = sample(pbr.emissive_map, in);
            e = e * Vec3{srgb_to_linear(t.x), srgb_to_linear(t.y), srgb_to_linear(t.z)};
        }
        return Vec4(detail::display(c + e, pbr), base.w);
    }
    // The shading normal: the interpolated one, with NormalMap perturbed by the map, n' =
    // normalize(t x + b y + n z) for the map's (x, y, z) = 2 texel - 1 (x and y times the scale), t the
    // tangent made orthogonal to n, b = w cross(n, t); turned toward the viewer on back faces (the
    // back of a bump is a dent).
    Vec3 normal(const FragmentIn<k_varyings>& in) const {
        Vec3 n = normalize(Layout::template of<Varying::normal>(in.v));
        if constexpr (NormalMap) {
            if (pbr.normal.texture) {
                const Vec4 tangent = Layout::template of<Varying::tangent>(in.v);
                const Vec3 t = normalize(tangent.xyz() - n * dot(n, tangent.xyz()));
                const Vec3 b = cross(n, t) * tangent.w;
                const Vec4 m = sample(pbr.normal, in);
                const float x = (2 * m.x - 1) * pbr.normal_scale, y = (2 * m.y - 1) * pbr.normal_scale, z = 2 * m.z - 1;
                const Vec3 mapped = normalize(t * x + b * y + n * z);
                if (dot(mapped, mapped) > 0) n = mapped;
            }
        }
        return in.front_facing ? n : -n;
    }
};
using Pbr = PbrShader<false, false>;
using PbrMasked = PbrShader<false, true>;
using PbrNormalMapped = PbrShader<true, false>;
using PbrNormalMappedMasked = PbrShader<true, true>;

// The lit mode's alpha-blended unlit materials (KHR_materials_unlit with alpha blending, e.g. the
// contact shadow's quad, facet/contact_shadow.hpp): PbrShader's colour for them, the display transform
// of the base colour (material x vertex colour x the decoded map) and its alpha, without the varyings
// and derivatives of the lit path, which unlit does not read. Only for maps not filtered trilinearly
// (the one filter that reads the derivatives). Its blended draws have a SIMD kernel
// (CompiledBlendPass, src/shade/blend_simd.cpp).
struct PbrUnlitBlended {
    using Layout = VaryingLayout<Varying::uv, Varying::colour>;
    static constexpr int k_varyings = Layout::count;
    MeshArrays mesh;
    ShadingUniforms u;
    PbrUniforms pbr;
    Vec4 vertex(std::uint32_t i, Varyings<k_varyings>& out) const { return Layout::vertex(mesh, u, i, out); }
    Vec4 fragment(const FragmentIn<k_varyings>& in) const {
        Vec4 base = Layout::of<Varying::colour>(in.v);
        if (pbr.base_colour.texture) {
            const Vec4 t = detail::sample_map(pbr.base_colour, Layout::of<Varying::uv>(in.v), {}, {});
            base = {base.x * srgb_to_linear(t.x), base.y * srgb_to_linear(t.y), base.z * srgb_to_linear(t.z), base.w * t.w};
        }
        return Vec4(detail::display(base.xyz(), pbr), base.w);
    }
};

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
FACET_COMPILED_VISIBLE_PASS(Pbr)
FACET_COMPILED_VISIBLE_PASS(PbrNormalMapped)
#undef FACET_COMPILED_VISIBLE_PASS

template <>
struct CompiledBlendPass<shaders::PbrUnlitBlended> {
    static constexpr bool available = true;
    static void run(const void* shader, const TriangleSetup& t, const TileCoverage& coverage, PixelRect tile,
                    const float* const (&var)[3], TargetView target, DepthTest test, std::uint32_t* owner,
                    std::uint32_t id);
};

// The shaders render_scene draws anti-aliased lines with (its draw_points_lines): their segments'
// blended pixels by a SIMD kernel (src/shade/line_aa_simd.cpp), the same bytes as shade_tile.
#define FACET_COMPILED_LINE_AA_PASS(S)                                                                  \
    template <>                                                                                       \
    struct CompiledLineAaPass<shaders::S> {                                                           \
        static constexpr bool available = true;                                                       \
        static void run(const void* shader, const TriangleSetup& t, const TileCoverage& coverage, PixelRect tile, \
                        const float* const (&var)[3], TargetView target, DepthTest test, std::uint32_t* owner, \
                        std::uint32_t id);                                                            \
    };
FACET_COMPILED_LINE_AA_PASS(LambertBaseColour)
FACET_COMPILED_LINE_AA_PASS(VertexColour)
#undef FACET_COMPILED_LINE_AA_PASS

// Vertex i's clip position as run_vertex_stage computes it (transform_points: the same bits).
inline Vec4 clip_position(const MeshArrays& mesh, const ShadingUniforms& u, std::uint32_t i) {
    Vec4 out;
    transform_points(u.clip_from_object, mesh.positions + i, 1, &out);
    return out;
}

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
        static Vec4 position(const shaders::S& s, std::uint32_t i) { return clip_position(s.mesh, s.u, i); } \
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
