// facet internals: the fragment stage, templated on the shader so fragment() inlines into the loop.
// In: a TriangleSetup, its TileCoverage and the three vertices' varyings. Per covered pixel: depth
// (linear in screen space) tested before the shader runs, perspective-correct varyings through
// q = 1/w, optional exact derivatives, the shader, then depth write and blending into the target.
// Out: pixels of the framebuffer inside this tile (the only thread that touches them).
#pragma once

#include <bit>
#include <optional>

#include "facet/detail/frame.hpp"
#include "facet/image.hpp"

namespace facet::detail {

template <DepthTest D>
inline bool depth_passes(float z, float stored) {
    if constexpr (D == DepthTest::less) return z < stored;
    if constexpr (D == DepthTest::lequal) return z <= stored;
    if constexpr (D == DepthTest::equal) return z == stored;
    if constexpr (D == DepthTest::greater) return z > stored;
    if constexpr (D == DepthTest::always) return true;
    return false;
}

struct TargetView {
    Rgba8* colour;
    float* depth;
    int stride;  // pixels per row
};

template <class S, DepthTest D, bool DepthWrite, Blend B>
void shade_tile(const S& shader, const TriangleSetup& t, const TileCoverage& cov, PixelRect tile,
                const float* const (&var)[3], TargetView target) {
    constexpr int N = S::k_varyings;
    constexpr int derivative_varyings = derivative_count<S>();
    // Barycentric form: v = v0 + b1 (v1 - v0) + b2 (v2 - v0), with b1, b2 perspective-correct.
    float v0[N > 0 ? N : 1], d1[N > 0 ? N : 1], d2[N > 0 ? N : 1];
    for (int k = 0; k < N; ++k) {
        v0[k] = var[0][k];
        d1[k] = var[1][k] - var[0][k];
        d2[k] = var[2][k] - var[0][k];
    }
    FragmentIn<N> in;
    in.front_facing = t.front_facing;

    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = tile.y0 + row;
        const float dy = (static_cast<float>(y) + 0.5f) - t.y0;
        Rgba8* colour_row = target.colour + static_cast<std::size_t>(y) * target.stride;
        float* depth_row = target.depth + static_cast<std::size_t>(y) * target.stride;
        while (mask) {
            const int x = tile.x0 + std::countr_zero(mask);
            mask &= mask - 1;
            const float dx = (static_cast<float>(x) + 0.5f) - t.x0;
            float z = t.z0 + t.dzdx * dx + t.dzdy * dy;
            z = z < 0 ? 0 : (z > 1 ? 1 : z);
            if (!depth_passes<D>(z, depth_row[x])) continue;

            const float q = t.q0 + t.dqdx * dx + t.dqdy * dy;
            const float w = 1.0f / q;
            const float b1 = (t.l1_0 + t.dl1dx * dx + t.dl1dy * dy) * w;
            const float b2 = (t.l2_0 + t.dl2dx * dx + t.dl2dy * dy) * w;
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

            Vec4 c;
            if constexpr (std::same_as<decltype(shader.fragment(in)), std::optional<Vec4>>) {
                std::optional<Vec4> r = shader.fragment(in);
                if (!r) continue;
                c = *r;
            } else {
                c = shader.fragment(in);
            }
            if constexpr (DepthWrite) depth_row[x] = z;
            if constexpr (B == Blend::alpha) {
                const Vec4 dst = to_vec4(colour_row[x]);
                const float a = c.w > 0 ? (c.w < 1 ? c.w : 1) : 0;
                c = Vec4{c.x * a + dst.x * (1 - a), c.y * a + dst.y * (1 - a), c.z * a + dst.z * (1 - a),
                         a + dst.w * (1 - a)};
            }
            colour_row[x] = to_rgba8(c);
        }
    }
}

}  // namespace facet::detail
