// facet: what a draw call is made of. The fixed-function state (culling, depth, blending), the
// varyings that flow from the vertex to the fragment stage, and the Shader concept: a shader is a
// plain type with vertex() and fragment() members, so draw<Shader> inlines them into the pixel loop.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <type_traits>

#include "facet/api.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

enum class CullMode { none, back, front };
enum class FrontFace { ccw, cw };  // winding of front faces as the viewer sees them
enum class DepthTest { never, less, lequal, equal, greater, always };
enum class Blend { none, alpha };  // alpha: src * a + dst * (1 - a)

// A rectangle of pixels; width == 0 means "the whole render target".
struct Rect {
    int x = 0, y = 0, width = 0, height = 0;
};

// What DrawState::clear clears the target to.
struct ClearValues {
    Vec4 colour{0, 0, 0, 0};
    float depth = 1.0f;
};

struct DrawState {
    CullMode cull = CullMode::back;
    FrontFace front_face = FrontFace::ccw;
    DepthTest depth_test = DepthTest::less;
    bool depth_write = true;
    Blend blend = Blend::none;
    // When set, the whole target (not only the viewport) is cleared to these values first, like a
    // render pass's clear load op: the same pixels as Framebuffer::clear followed by the draw, but
    // each tile is cleared by the thread that draws it, just before it does, instead of in a
    // separate pass over the whole framebuffer.
    std::optional<ClearValues> clear = std::nullopt;
    // false: nothing reads the target's depth after this draw, so the draw need not store it (a
    // render pass's "don't care" store): the colour is the same, the target's depth afterwards is
    // unspecified. Pays for a draw that clears and is the frame's only draw: its depth stays in the
    // tiles' own buffers, and the empty tiles get only their clear colour (at 1920x1080 half of the
    // 16 MB a clear writes). Draws that need the target's depth themselves (the one-pass order,
    // every batch but the last) still store it.
    bool keep_depth = true;
    Rect viewport;  // clip space maps onto this rectangle; pixels outside it are never written
};

// N floats that the vertex stage writes per vertex and the fragment stage receives interpolated
// (perspective-correct) per pixel.
template <int N>
struct Varyings {
    std::array<float, (N > 0 ? N : 1)> v{};
    constexpr float& operator[](int i) { return v[static_cast<std::size_t>(i)]; }
    constexpr float operator[](int i) const { return v[static_cast<std::size_t>(i)]; }
    Vec2 vec2(int i) const { return {v[i], v[i + 1]}; }
    Vec3 vec3(int i) const { return {v[i], v[i + 1], v[i + 2]}; }
    Vec4 vec4(int i) const { return {v[i], v[i + 1], v[i + 2], v[i + 3]}; }
    void set(int i, Vec2 a) { v[i] = a.x, v[i + 1] = a.y; }
    void set(int i, Vec3 a) { v[i] = a.x, v[i + 1] = a.y, v[i + 2] = a.z; }
    void set(int i, Vec4 a) { v[i] = a.x, v[i + 1] = a.y, v[i + 2] = a.z, v[i + 3] = a.w; }
};

// Everything the fragment stage knows about one pixel. ddx/ddy (the exact screen-space derivatives
// of the perspective-correct varyings) are filled only for shaders that set k_derivatives = true;
// they are what flat normals and texture mip selection need.
template <int N>
struct FragmentIn {
    Varyings<N> v;
    Varyings<N> ddx, ddy;
    Vec2 pos_screen;   // pixel centre, origin top-left
    float depth = 0;   // window depth in [0, 1]
    bool front_facing = true;
};

namespace detail {
// How many leading varyings get derivatives: all of them with k_derivatives = true, or the first
// k_derivative_count (e.g. just the uv pair), which saves work per pixel.
template <class S>
constexpr int derivative_count() {
    if constexpr (requires { S::k_derivative_count; }) return S::k_derivative_count;
    else if constexpr (requires { S::k_derivatives; }) return S::k_derivatives ? S::k_varyings : 0;
    else return 0;
}
}  // namespace detail

// A shader type:
//   static constexpr int k_varyings;                                   number of floats passed on
//   Vec4 vertex(std::uint32_t index, Varyings<k_varyings>& out) const;  returns pos_clip
//   fragment(const FragmentIn<k_varyings>& in) const  -> Vec4 colour, or std::optional<Vec4>
//                                                         where nullopt discards the pixel
// Optional: static constexpr bool k_derivatives = true; to receive in.ddx / in.ddy of every varying,
// or static constexpr int k_derivative_count = K; for the first K varyings only.
// fragment() must be a pure function of its input: without blending or discard it is called only for
// the pixels that end up visible (hidden surfaces are resolved by depth first). A shader that must
// see every fragment passing the depth test sets static constexpr bool k_shade_hidden = true.
template <class S>
concept Shader = requires(const S& s, std::uint32_t index, Varyings<S::k_varyings>& out,
                          const FragmentIn<S::k_varyings>& in) {
    { S::k_varyings } -> std::convertible_to<int>;
    { s.vertex(index, out) } -> std::same_as<Vec4>;
    requires std::same_as<decltype(s.fragment(in)), Vec4> ||
                 std::same_as<decltype(s.fragment(in)), std::optional<Vec4>>;
};

// A shader from two lambdas, for quick work:
//   auto shader = make_shader<3>([&](uint32_t i, Varyings<3>& out) { ...; return pos_clip; },
//                                [&](const FragmentIn<3>& in) { return Vec4{...}; });
template <int N, class VertexFn, class FragmentFn>
struct LambdaShader {
    static constexpr int k_varyings = N;
    VertexFn vertex_fn;
    FragmentFn fragment_fn;
    Vec4 vertex(std::uint32_t index, Varyings<N>& out) const { return vertex_fn(index, out); }
    auto fragment(const FragmentIn<N>& in) const { return fragment_fn(in); }
};

template <int N, class VertexFn, class FragmentFn>
LambdaShader<N, VertexFn, FragmentFn> make_shader(VertexFn vertex_fn, FragmentFn fragment_fn) {
    return {std::move(vertex_fn), std::move(fragment_fn)};
}

// What the indices of a draw assemble: triangles (three indices each), points (one each, drawn as
// screen-space splats) or line segments (two each, drawn as screen-space quads of a width in pixels).
// The coverage rules of points and lines are in README.md ("Points and lines"); their splats and
// quads go through the same tiles, depth test and shading as triangles.
enum class Topology { triangles, points, lines };
enum class PointShape { round, square };

// The size of points and the width of lines. A point covers the pixel centres within size / 2 of its
// projected centre (round), or inside the size x size square around it (square); a segment the pixel
// centres within width / 2 of it, without caps; consecutive segments that share a vertex (the second
// index of one is the first of the next) meet in a mitred join, so strips have neither gaps nor
// double hits. With `model_scale` > 0 the point size is in model units instead: a point at clip w
// is size * model_scale / w pixels (model_scale: pixels per unit at w = 1, e.g. the projection's
// y scale times half the viewport's height), at most k_max_point_size; such a size may be any number
// in (0, k_model_point_size_bound).
// With `line_aa` lines are anti-aliased instead (README.md, "Anti-aliased lines"): each covers the
// band of half-width width / 2 + 1/2 with a coverage of min(1, the pixel centre's distance to the
// band's edge), its colour blended over what is behind by it (the draw's blending and depth writes
// are replaced by alpha blending without depth writes); joins are split by the mitre as above, so a
// strip blends each pixel once.
struct PrimitiveStyle {
    static constexpr float k_max_point_size = 256.0f;  // pixels; sizes and widths must be in (0, this]
    static constexpr float k_model_point_size_bound = 1e30f;  // sizes in model units must be in (0, this)
    static constexpr float k_max_line_width = 256.0f;
    float point_size = 1.0f;
    PointShape point_shape = PointShape::round;
    float model_scale = 0.0f;
    float line_width = 1.0f;
    bool line_aa = false;
};

// What to draw: `vertex_count` vertices, assembled into primitives of `topology` by `indices` or,
// when indices is empty, by consecutive vertices.
struct DrawInput {
    std::uint32_t vertex_count = 0;
    std::span<const std::uint32_t> indices;
    Topology topology = Topology::triangles;
    PrimitiveStyle style{};  // points and lines
    // Indices per primitive of the topology.
    int arity() const { return topology == Topology::triangles ? 3 : topology == Topology::lines ? 2 : 1; }
    // The primitives assembled; a trailing partial one (index count not a multiple of the arity) is ignored.
    std::size_t primitive_count() const {
        const std::size_t n = indices.empty() ? vertex_count : indices.size();
        return n / static_cast<std::size_t>(arity());
    }
    // The triangles of a triangle draw (0 for points and lines).
    std::size_t triangle_count() const { return topology == Topology::triangles ? primitive_count() : 0; }
};

// What a draw call did, for tests, statistics and warnings.
struct DrawStats {
    std::uint64_t triangles_in = 0;        // assembled from the input
    std::uint64_t triangles_invalid = 0;   // dropped: index out of range or non-finite position
    std::uint64_t triangles_culled = 0;    // dropped: back/front face or zero area
    std::uint64_t triangles_clipped = 0;   // crossed a clip plane and were cut
    std::uint64_t triangles_rasterized = 0;  // set up and binned (after clipping; points' and lines' too)
    std::uint64_t points_in = 0, points_invalid = 0;  // invalid: index out of range or non-finite position
    std::uint64_t segments_in = 0, segments_invalid = 0;

    // The counts of several draws, summed.
    DrawStats& operator+=(const DrawStats& s) {
        triangles_in += s.triangles_in;
        triangles_invalid += s.triangles_invalid;
        triangles_culled += s.triangles_culled;
        triangles_clipped += s.triangles_clipped;
        triangles_rasterized += s.triangles_rasterized;
        points_in += s.points_in, points_invalid += s.points_invalid;
        segments_in += s.segments_in, segments_invalid += s.segments_invalid;
        return *this;
    }
};

}  // namespace facet
FACET_API_END
