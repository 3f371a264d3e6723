// facet shade: the SIMD kernel of the lit mode's alpha-blended unlit draws (shaders::PbrUnlitBlended,
// e.g. the contact shadow's quad), compiled once per ISA by Highway. In: one triangle's set-up, its
// coverage of a tile and its vertices' varyings. Out: its covered pixels that pass the depth test,
// blended over the target (no depth written), the bytes of the specification,
// detail::shade_tile<PbrUnlitBlended, false, Blend::alpha> (fragment.hpp). Not other shaders, nor
// depth-writing or opaque draws.
//
// A vector of covered pixels of one row at a time: depth and the depth test, the perspective-correct
// uv and colour (fragment_at's operations in its order), the base map's bilinear alpha
// (Texture::sample's arithmetic: clamped coordinates, floor, the four texels' mix), the blend and
// to_rgba8. The colour's RGB is the display transform of black wherever the material and vertex
// colours make the base colour's RGB +0 (a black material, as the shadow's): computed once per call;
// lanes of any other colour go through the specification, as do draws whose map is transformed,
// wraps other than clamp or is not filtered bilinearly.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/blend_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "facet/detail/fragment.hpp"
#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using Shader = shaders::PbrUnlitBlended;

// The base map's alpha at (u, v) in [0, 255] (before Texture::sample's division by 255): its
// bilinear filter of level 0 with clamped coordinates, lane by lane as footprint() and bilinear().
struct AlphaMap {
    const std::uint32_t* texels;  // Rgba8, alpha in the top byte
    int width, height;

    HWY_INLINE VF axis(VF c, int size, hn::Vec<DI>& i0, hn::Vec<DI>& i1) const {
        const DF df;
        const DI di;
        c = hn::IfThenElseZero(hn::IsFinite(c), c);  // finite_or_zero
        c = hn::IfThenElse(hn::Lt(c, hn::Zero(df)), hn::Zero(df),
                           hn::IfThenElse(hn::Gt(c, hn::Set(df, 1.0f)), hn::Set(df, 1.0f), c));
        const VF x = hn::Sub(hn::Mul(c, hn::Set(df, static_cast<float>(size))), hn::Set(df, 0.5f));
        const VF x0 = hn::Floor(x);
        const auto first = hn::ConvertTo(di, x0);  // in [-1, size]
        const auto zero = hn::Zero(di), last = hn::Set(di, size - 1);
        i0 = hn::Min(hn::Max(first, zero), last);
        i1 = hn::Min(hn::Max(hn::Add(first, hn::Set(di, 1)), zero), last);
        return hn::Sub(x, x0);
    }
    HWY_INLINE VF texel(hn::Vec<DI> x, hn::Vec<DI> y) const {
        const DF df;
        const DU du;
        const DI di;
        const auto index = hn::Add(hn::Mul(y, hn::Set(di, width)), x);
        return hn::ConvertTo(df, hn::BitCast(di, hn::ShiftRight<24>(hn::GatherIndex(du, texels, index))));
    }
    HWY_INLINE VF operator()(VF u, VF v) const {
        hn::Vec<DI> x0, x1, y0, y1;
        const VF tx = axis(u, width, x0, x1), ty = axis(v, height, y0, y1);
        auto mix = [](VF a, VF b, VF t) { return hn::Add(a, hn::Mul(hn::Sub(b, a), t)); };
        const VF top = mix(texel(x0, y0), texel(x1, y0), tx);
        const VF bottom = mix(texel(x0, y1), texel(x1, y1), tx);
        return mix(top, bottom, ty);
    }
};

// The pixels of a row whose bilinear samples of the map may have alpha: the others blend to the
// target's own bytes (alpha 0: the display colour, in [0, 1], times 0 plus each byte / 255 times 1
// rounds back to the byte). A sample has alpha only where u and v reach the texels of the map's
// alpha_bounds; those ranges are widened here by a texel and the pixels found by a pixel, far more
// than the kernel's float rounding moves its uv. Along a row u and v are quotients of linear
// functions of x with the denominator q, > 0 at the row's ends and so between them: each bound on
// u or v is a linear inequality in x, solved in double.
template <int N>
struct AlphaColumns {
    const TriangleSetup& t;
    const float* planes;
    int uv_at;
    PixelRect tile;
    bool any = true;    // without a map: every pixel
    bool none = false;  // no texel has alpha
    double lo[2] = {-HUGE_VAL, -HUGE_VAL}, hi[2] = {HUGE_VAL, HUGE_VAL};

    AlphaColumns(const Texture* texture, const TriangleSetup& setup, const float* p, int at, PixelRect r)
        : t(setup), planes(p), uv_at(at), tile(r) {
        if (!texture) return;
        any = false;
        const TexelRect b = texture->alpha_bounds();
        none = b.x0 == b.x1;
        // footprint() takes texels floor(c * size - 0.5) and the next, c clamped to [0, 1]: one of
        // [first, end) only when c >= (first - 0.5) / size and c < (end + 0.5) / size.
        auto range = [](int first, int end, int size, double& l, double& h) {
            const double texel = 1.0 / size;
            if (first > 0) l = (first - 0.5) * texel - texel;
            if (end < size) h = (end + 0.5) * texel + texel;
        };
        range(b.x0, b.x1, texture->width(), lo[0], hi[0]);
        range(b.y0, b.y1, texture->height(), lo[1], hi[1]);
    }

    std::uint64_t operator()(int y) const {
        const int width = tile.x1 - tile.x0;
        const std::uint64_t all = width >= 64 ? ~0ull : (1ull << width) - 1;
        if (any) return all;
        if (none) return 0;
        const double dy = y + 0.5 - t.y0, x_offset = 0.5 - t.x0;
        const double qa = t.dqdx, qb = t.q0 + t.dqdx * x_offset + t.dqdy * dy;
        const double l1a = t.dl1dx, l1b = t.dl1dx * x_offset + t.dl1dy * dy;
        const double l2a = t.dl2dx, l2b = t.dl2dx * x_offset + t.dl2dy * dy;
        const double first = tile.x0, last = tile.x1 - 1;
        if (!(qa * first + qb > 0) || !(qa * last + qb > 0)) return all;
        double xa = first, xb = last;
        // a x + b >= 0 (a x + b <= 0 with `below`) for x in [xa, xb].
        auto keep = [&](double a, double b, bool below) {
            if (below) a = -a, b = -b;
            if (a > 0) xa = std::max(xa, -b / a);
            else if (a < 0) xb = std::min(xb, -b / a);
            else if (b < 0) xb = xa - 1;
        };
        for (int k = 0; k < 2; ++k) {
            const double p0 = planes[uv_at + k], p1 = planes[N + uv_at + k], p2 = planes[2 * N + uv_at + k];
            const double ua = p0 * qa + p1 * l1a + p2 * l2a, ub = p0 * qb + p1 * l1b + p2 * l2b;
            for (const double x : {first, last})
                if (!(std::abs((ua * x + ub) / (qa * x + qb)) < 16)) return all;  // also NaN
            if (lo[k] > -HUGE_VAL) keep(ua - lo[k] * qa, ub - lo[k] * qb, false);  // u >= lo
            if (hi[k] < HUGE_VAL) keep(ua - hi[k] * qa, ub - hi[k] * qb, true);    // u <= hi
        }
        if (!(xa <= xb)) return 0;
        const int from = std::max(static_cast<int>(std::ceil(xa)) - 1, tile.x0) - tile.x0;
        const int to = std::min(static_cast<int>(std::floor(xb)) + 1, tile.x1 - 1) - tile.x0;
        if (from > to) return 0;
        return (to - from + 1 >= 64 ? ~0ull : ((1ull << (to - from + 1)) - 1)) << from;
    }
};

}  // namespace

void BlendUnlit(const Shader& s, const TriangleSetup& t, const TileCoverage& cov, PixelRect tile,
                const float* const (&var)[3], TargetView target, DepthTest test) {
    constexpr int N = Shader::k_varyings;
    constexpr int uv_at = Shader::Layout::at(shaders::Varying::uv), colour_at = Shader::Layout::at(shaders::Varying::colour);
    const DF df;
    const DU du;
    constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
    constexpr std::uint64_t lane_bits = lanes >= 64 ? ~0ull : (1ull << lanes) - 1;
    const VaryingPlanes<N> planes(var);
    auto splat_plane = [&](int k) { return hn::Set(df, planes.p[k]); };
    const Vec3 black = shaders::detail::display({0, 0, 0}, s.pbr);
    const VF black_r = hn::Set(df, black.x), black_g = hn::Set(df, black.y), black_b = hn::Set(df, black.z);
    const Texture* texture = s.pbr.base_colour.texture;
    const AlphaMap map = texture ? AlphaMap{reinterpret_cast<const std::uint32_t*>(texture->level(0).pixels.data()),
                                            texture->level(0).width, texture->level(0).height}
                                 : AlphaMap{nullptr, 0, 0};
    const DepthTestLanes depth_test(depth_pass_set(test));
    HWY_ALIGN float iota[lanes];
    HWY_ALIGN std::uint32_t bit_of[lanes];
    for (int l = 0; l < lanes; ++l) iota[l] = static_cast<float>(l), bit_of[l] = 1u << l;
    const VF lane_x = hn::Load(df, iota);
    const auto lane_bit = hn::Load(du, bit_of);
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f);

    const AlphaColumns<N> with_alpha(texture, t, planes.p, uv_at, tile);
    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        const int y = tile.y0 + row;
        std::uint64_t mask = cov.rows[row];
        mask &= with_alpha(y);
        Rgba8* colour_row = target.colour + static_cast<std::size_t>(y) * target.stride;
        float* depth_row = target.depth + static_cast<std::size_t>(y) * target.stride;
        const float dy_scalar = (static_cast<float>(y) + 0.5f) - t.y0;
        const VF dy = hn::Set(df, dy_scalar);
        while (mask) {
            const int i = std::countr_zero(mask);
            const std::uint64_t bits = (mask >> i) & lane_bits;
            mask &= ~(lane_bits << i);
            const int x = tile.x0 + i;
            const int n = 64 - std::countl_zero(bits);  // the lanes up to the last covered one: inside the tile
            const MF covered = hn::RebindMask(df, hn::TestBit(hn::Set(du, static_cast<std::uint32_t>(bits)), lane_bit));
            // Loads and stores of n pixels only: the tile may end before a whole vector.
            HWY_ALIGN float depth_in[lanes];
            HWY_ALIGN std::uint32_t colour_io[lanes];
            std::memcpy(depth_in, depth_row + x, sizeof(float) * static_cast<std::size_t>(n));
            std::memcpy(colour_io, colour_row + x, sizeof(std::uint32_t) * static_cast<std::size_t>(n));
            for (int l = n; l < lanes; ++l) depth_in[l] = 0, colour_io[l] = 0;

            // depth_at and the depth test (depth_passes_in).
            const VF dx = hn::Sub(hn::Add(hn::Add(hn::Set(df, static_cast<float>(x)), lane_x), half), hn::Set(df, t.x0));
            const MF drawn = hn::And(covered, depth_test.passes(depth_lanes(t, dx, dy), hn::Load(df, depth_in)));
            if (hn::AllFalse(df, drawn)) continue;

            // fragment_at's interpolation of the uv and the colour.
            const VF q = hn::Add(hn::Add(hn::Set(df, t.q0), hn::Mul(hn::Set(df, t.dqdx), dx)), hn::Mul(hn::Set(df, t.dqdy), dy));
            const VF w = hn::Div(one, q);
            const VF b1 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(hn::Set(df, t.dl1dx), dx)), hn::Mul(hn::Set(df, t.dl1dy), dy)), w);
            const VF b2 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(hn::Set(df, t.dl2dx), dx)), hn::Mul(hn::Set(df, t.dl2dy), dy)), w);
            auto varying = [&](int k) {
                return hn::Add(hn::Add(splat_plane(k), hn::Mul(b1, splat_plane(N + k))), hn::Mul(b2, splat_plane(2 * N + k)));
            };
            // The RGB of the base colour is +0 (times the map's decoded RGB, >= 0 and finite, still +0)
            // exactly where the colour varying's is: those lanes are black; the others need the specification.
            const auto bits_of = [&](int k) { return hn::BitCast(du, varying(colour_at + k)); };
            const auto rgb_bits = hn::Or(hn::Or(bits_of(0), bits_of(1)), bits_of(2));
            const MF scalar = hn::And(drawn, hn::RebindMask(df, hn::Ne(rgb_bits, hn::Zero(du))));
            VF alpha = varying(colour_at + 3);
            if (texture) alpha = hn::Mul(alpha, hn::Div(map(varying(uv_at), varying(uv_at + 1)), hn::Set(df, 255.0f)));

            // The blend over the target and to_rgba8.
            const auto dst = hn::Load(du, colour_io);
            const ColourLanes blended = blend_over(black_r, black_g, black_b, blend_alpha(alpha), dst);
            const MF vector_lanes = hn::AndNot(scalar, drawn);
            hn::Store(hn::IfThenElse(hn::RebindMask(du, vector_lanes), to_rgba8(blended), dst), du, colour_io);
            std::memcpy(colour_row + x, colour_io, sizeof(std::uint32_t) * static_cast<std::size_t>(n));
            if (hn::AllFalse(df, scalar)) continue;
            TileCoverage rest;
            rest.first_row = rest.last_row = row;
            rest.rows[row] = mask_bits(scalar) << i;
            shade_tile<Shader, false, Blend::alpha>(s, test, t, rest, tile, var, target);
        }
    }
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(BlendUnlit);

void CompiledBlendPass<shaders::PbrUnlitBlended>::run(const void* shader, const TriangleSetup& t,
                                                      const TileCoverage& coverage, PixelRect tile,
                                                      const float* const (&var)[3], TargetView target, DepthTest test,
                                                      std::uint32_t* owner, std::uint32_t id) {
    const auto& s = *static_cast<const shaders::PbrUnlitBlended*>(shader);
    const MapBinding& map = s.pbr.base_colour;
    const bool kernel_reads_map = !map.texture || (!map.transformed && map.sampler.filter == Filter::bilinear &&
                                                   map.sampler.wrap_u == Wrap::clamp && map.sampler.wrap_v == Wrap::clamp);
    if (use_scalar_kernels() || !kernel_reads_map)
        return shade_tile<shaders::PbrUnlitBlended, false, Blend::alpha>(s, test, t, coverage, tile, var, target, owner, id);
    HWY_DYNAMIC_DISPATCH(BlendUnlit)(s, t, coverage, tile, var, target, test);
}

}  // namespace facet::detail
#endif
