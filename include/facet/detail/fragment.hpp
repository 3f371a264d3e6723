// facet internals: the fragment stage, templated on the shader so that fragment() inlines into the
// pixel loops. In: one triangle's set-up record, varyings and TileCoverage in a tile (the one-pass
// order), or a VisibleTile (the visible-only order). Per pixel: depth (linear in screen space),
// perspective-correct varyings through q = 1/w, optional exact derivatives, the shader; in the
// one-pass order also the depth test before the shader, the depth write and blending. Out: pixels
// of one tile of the target (the only thread that touches them). Does not choose the order
// (draw_order.hpp), walk the tiles or run the depth pass (src/tile/).
//
// Two orders, one result. shade_tile draws a triangle's pixels as they come (needed for blending and
// discard). When neither is used, a pixel's final colour is that of the last triangle to pass the
// depth test there, so the tile pass runs every triangle's depth test first and hands over which
// triangle is visible at each pixel (VisibleTile), and shade_visible calls the shader once per
// visible pixel. Depth tests and writes happen in the same order with the same values, and each
// visible pixel is shaded by the same code (fragment_at) from the same inputs, so the bytes are those
// of the one-pass order; hidden pixels are simply never shaded.
#pragma once

#include <bit>
#include <concepts>
#include <cstdint>
#include <optional>

#include "facet/api.hpp"
#include "facet/detail/frame.hpp"
#include "facet/detail/line_aa.hpp"
#include "facet/detail/visible_tile.hpp"
#include "facet/image.hpp"

FACET_API_BEGIN
namespace facet::detail {

template <class S>
constexpr bool shader_discards() {
    return std::same_as<decltype(std::declval<const S&>().fragment(std::declval<const FragmentIn<S::k_varyings>&>())),
                        std::optional<Vec4>>;
}

// Shaders may set k_shade_hidden = true to be called for every fragment that passes the depth test,
// hidden later or not (e.g. to count them); otherwise only visible pixels are shaded when possible.
template <class S>
constexpr bool shades_visible_only() {
    if constexpr (requires { S::k_shade_hidden; }) return !S::k_shade_hidden;
    return true;
}

template <class S, Blend B>
constexpr bool draws_visible_only() {
    return B == Blend::none && !shader_discards<S>() && shades_visible_only<S>();
}

// Window depth of the pixel (x, y) on triangle t, clamped to [0, 1].
inline float depth_at(const TriangleSetup& t, int x, int y) {
    const float dx = (static_cast<float>(x) + 0.5f) - t.x0, dy = (static_cast<float>(y) + 0.5f) - t.y0;
    const float z = t.z0 + t.dzdx * dx + t.dzdy * dy;
    return z < 0 ? 0 : (z > 1 ? 1 : z);
}

template <int N>
struct VaryingPlanes {
    float p[N > 0 ? 3 * N : 1];
    explicit VaryingPlanes(const float* const (&var)[3]) { write_varying_planes(var, N, p); }
};

// The shader's result at pixel (x, y) of triangle t, whose depth there is z: fills `in` and calls
// fragment(). Both drawing orders go through here.
template <class S>
inline auto fragment_at(const S& shader, const TriangleSetup& t, const float* planes, int x, int y, float z,
                        FragmentIn<S::k_varyings>& in) {
    constexpr int N = S::k_varyings;
    constexpr int derivative_varyings = derivative_count<S>();
    const float dx = (static_cast<float>(x) + 0.5f) - t.x0, dy = (static_cast<float>(y) + 0.5f) - t.y0;
    const float q = t.q0 + t.dqdx * dx + t.dqdy * dy;
    const float w = 1.0f / q;
    // The planes' value at (x0, y0) is 0; it is still added, so a -0 product sums to +0 as it always has.
    const float b1 = (0.0f + t.dl1dx * dx + t.dl1dy * dy) * w;
    const float b2 = (0.0f + t.dl2dx * dx + t.dl2dy * dy) * w;
    const float *v0 = planes, *d1 = planes + N, *d2 = planes + 2 * N;
    for (int k = 0; k < N; ++k) in.v[k] = v0[k] + b1 * d1[k] + b2 * d2[k];
    if constexpr (derivative_varyings > 0) {
        // d(l/q)/dx = (dl/dx - (l/q) dq/dx) / q for each perspective-correct barycentric.
        const float b1x = (t.dl1dx - b1 * t.dqdx) * w, b1y = (t.dl1dy - b1 * t.dqdy) * w;
        const float b2x = (t.dl2dx - b2 * t.dqdx) * w, b2y = (t.dl2dy - b2 * t.dqdy) * w;
        for (int k = 0; k < derivative_varyings; ++k) {
            in.ddx[k] = b1x * d1[k] + b2x * d2[k];
            in.ddy[k] = b1y * d1[k] + b2y * d2[k];
        }
    }
    in.pos_screen = {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
    in.depth = z;
    in.front_facing = t.front_facing;
    return shader.fragment(in);
}

// A depth test as the set of comparison outcomes it passes (bit 1: z < stored, bit 2: equal, bit 4:
// greater, bit 0: unordered, i.e. a NaN), for depth_passes_in below.
inline std::uint32_t depth_pass_set(DepthTest test) {
    switch (test) {
        case DepthTest::less: return 1u << 1;
        case DepthTest::lequal: return 1u << 1 | 1u << 2;
        case DepthTest::equal: return 1u << 2;
        case DepthTest::greater: return 1u << 4;
        case DepthTest::always: return 1u << 0 | 1u << 1 | 1u << 2 | 1u << 4;
        case DepthTest::never: break;
    }
    return 0;
}

// Whether z passes the depth test whose depth_pass_set is `pass_set` against `stored`, without a
// branch: the one-pass order takes the depth test as a run-time argument, so it is not instantiated
// once per depth test (that multiplied every shader's fragment stage by five).
[[gnu::always_inline]] inline bool depth_passes_in(std::uint32_t pass_set, float z, float stored) {
    const unsigned outcome = unsigned{z < stored} | unsigned{z == stored} << 1 | unsigned{z > stored} << 2;
    return (pass_set >> outcome) & 1u;
}

// One pass: test, shade, write each covered pixel of one triangle in turn. With `owner` (render
// passes), `id` is written at each pixel whose depth the triangle writes (rows VisibleTile::k_row
// apart from the tile's corner), so that the passes see what the depth buffer holds. With LineAa (an
// anti-aliased segment, blended), each pixel's alpha is scaled by its coverage (line_aa.hpp) and
// pixels of no coverage are skipped.
template <class S, bool DepthWrite, Blend B, bool LineAa>
void shade_covered_pixels(const S& shader, DepthTest test, const TriangleSetup& t, const TileCoverage& cov,
                          PixelRect tile, const float* const (&var)[3], TargetView target, std::uint32_t* owner,
                          std::uint32_t id) {
    const VaryingPlanes<S::k_varyings> planes(var);
    FragmentIn<S::k_varyings> in;
    const std::uint32_t pass_set = depth_pass_set(test);
    LineAaCoverage aa;
    if constexpr (LineAa) aa = LineAaCoverage(t);
    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = tile.y0 + row;
        Rgba8* colour_row = target.colour + static_cast<std::size_t>(y) * target.stride;
        float* depth_row = target.depth + static_cast<std::size_t>(y) * target.stride;
        while (mask) {
            const int x = tile.x0 + std::countr_zero(mask);
            mask &= mask - 1;
            float coverage = 1.0f;
            if constexpr (LineAa) {
                coverage = aa.at(x, y);
                if (coverage == 0) continue;
            }
            const float z = depth_at(t, x, y);
            if (!depth_passes_in(pass_set, z, depth_row[x])) continue;
            Vec4 c;
            if constexpr (shader_discards<S>()) {
                const std::optional<Vec4> r = fragment_at(shader, t, planes.p, x, y, z, in);
                if (!r) continue;
                c = *r;
            } else {
                c = fragment_at(shader, t, planes.p, x, y, z, in);
            }
            if constexpr (DepthWrite) {
                depth_row[x] = z;
                if (owner) owner[row * VisibleTile::k_row + (x - tile.x0)] = id;
            }
            if constexpr (B == Blend::alpha) {
                const Vec4 dst = to_vec4(colour_row[x]);
                float a = c.w > 0 ? (c.w < 1 ? c.w : 1) : 0;
                if constexpr (LineAa) a *= coverage;
                c = Vec4{c.x * a + dst.x * (1 - a), c.y * a + dst.y * (1 - a), c.z * a + dst.z * (1 - a),
                         a + dst.w * (1 - a)};
            }
            colour_row[x] = to_rgba8(c);
        }
    }
}

template <class S, bool DepthWrite, Blend B>
void shade_tile(const S& shader, DepthTest test, const TriangleSetup& t, const TileCoverage& cov, PixelRect tile,
                const float* const (&var)[3], TargetView target, std::uint32_t* owner = nullptr,
                std::uint32_t id = 0) {
    // Anti-aliased lines are drawn blended without depth writes (Renderer::draw), so only that
    // instance looks at the flag.
    if constexpr (B == Blend::alpha && !DepthWrite)
        if (t.line_aa) return shade_covered_pixels<S, DepthWrite, B, true>(shader, test, t, cov, tile, var, target, owner, id);
    shade_covered_pixels<S, DepthWrite, B, false>(shader, test, t, cov, tile, var, target, owner, id);
}

// Pass two of the visible-only order: the shader once per visible pixel, with the triangle that owns
// it. This is the scalar specification; built-in shaders also have SIMD kernels with the same
// results (CompiledVisiblePass). Shades the pixels of row y whose bits are set in `mask` (bit i:
// pixel tile.rect.x0 + i).
template <class S>
[[gnu::always_inline]] inline void shade_visible_pixels(const S& shader, const VisibleTile& tile, TargetView target,
                                                        int y, std::uint64_t mask) {
    FragmentIn<S::k_varyings> in;
    const std::uint32_t* owner_row = tile.owner + (y - tile.rect.y0) * VisibleTile::k_row;
    Rgba8* colour_row = target.colour + target.at(tile.rect.x0, y);
    for (; mask; mask &= mask - 1) {
        const int i = std::countr_zero(mask), x = tile.rect.x0 + i;
        const std::uint32_t owner = owner_row[i];
        if (owner == VisibleTile::k_no_owner) continue;
        const TriangleSetup& t = *tile.triangles[owner];
        const float* planes = tile.record(owner) + k_shading_head;
        colour_row[i] = to_rgba8(fragment_at(shader, t, planes, x, y, depth_at(t, x, y), in));
    }
}

// Flattened: GCC otherwise keeps fragment() and to_rgba8 as calls here (measured: 10% of a bunny frame).
template <class S>
[[gnu::flatten]] void shade_visible(const S& shader, const VisibleTile& tile, TargetView target) {
    for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
        shade_visible_pixels(shader, tile, target, y, tile.covered[y - tile.rect.y0]);
}

}  // namespace facet::detail
FACET_API_END
