// facet shade: the SIMD kernel of anti-aliased line segments (PrimitiveStyle::line_aa) for the shaders
// lines are drawn with (render_scene's draw_points_lines: shaders::LambertBaseColour in the lambert
// mode, shaders::VertexColour without normals), compiled once per ISA by Highway. In: one segment
// record with line_aa set, its coverage of a tile and its vertices' varyings. Out: its covered pixels of
// non-zero coverage that pass the depth test, blended over the target by alpha x coverage (no depth
// written): the bytes of the specification, detail::shade_tile<S, false, Blend::alpha> (fragment.hpp,
// with LineAaCoverage of line_aa.hpp). Not other records (the two triangles of a quad that is not
// strictly convex), shaders or draws.
//
// A vector of the record's covered pixels at a time, from any of its rows (a thin segment covers a
// few pixels of each row: a vector per row would be mostly empty), the target's depth and colour read
// and written back pixel by pixel: each fading edge's exact integer value in double lanes (integers
// below 2^41, so every sum and product is exact and equals the int64 value), times 1 / |gradient| in
// double, the minimum with 1, the float conversion (LineAaCoverage::at); then depth and the depth
// test, fragment_at's interpolation, the shader's lanes (visible_simd-inl.h), the blend and to_rgba8,
// each operation in the specification's order. The Lambert lanes may give a zero of the other sign
// than fragment() (their k_signed_zeros); the blend c * a + dst * (1 - a) with a in [0, 1] and
// dst >= 0 adds +0 or more to it, which makes either sign +0. Lanes whose normal has no exact vector
// form (normalize's rare cases) go to the specification pixel by pixel.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/line_aa_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

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

// The lane-wide fragment() of shaders::LambertBaseColour: shade(base colour, lambert_term(normalize(n))).
struct LambertBaseColourLineLanes {
    using S = shaders::LambertBaseColour;
    static constexpr int N = S::k_varyings;
    const S& s;
    bool grey_light = grey_lights(s.u);
    bool no_fill = fill_is_dark(s.u.fill);
    HWY_INLINE ColourLanes operator()(LanesIn<N>& in) const {
        const Vec3Lanes n = normalize(vec3_lanes<S::Layout, shaders::Varying::normal>(in.v), in.scalar, k_min_normal_length);
        return shade(albedo_lanes(s, in), lambert_term(n, s.u, grey_light, no_fill));
    }
};

// The lane-wide fragment() of shaders::VertexColour: the colour varying.
struct VertexColourLineLanes {
    using S = shaders::VertexColour;
    static constexpr int N = S::k_varyings;
    const S& s;
    HWY_INLINE ColourLanes operator()(LanesIn<N>& in) const { return colour_lanes<S::Layout>(in.v); }
};

// std::min(d, v) of double lanes: v < d ? v : d (x86's min returns its second operand unless the
// first is less: one instruction).
template <class VD>
HWY_INLINE VD min_into(VD d, VD v) {
#if HWY_ARCH_X86
    return hn::Min(v, d);
#else
    return hn::IfThenElse(hn::Lt(v, d), v, d);
#endif
}

// Up to a vector of a record's covered pixels, from any rows, one per lane: their columns and rows,
// and the target's depth and colour there (read before, written back after, by the pixel: a thin
// segment covers a few pixels of each row, so a vector per row would be mostly empty).
template <int L>
struct PixelLanes {
    HWY_ALIGN std::int32_t x[L], y[L];
    HWY_ALIGN float depth[L];
    HWY_ALIGN std::uint32_t colour[L];
    HWY_ALIGN std::uint32_t out[L];
    int n = 0;
};

template <class Lanes>
void BlendLineAa(const Lanes& lanes, const TriangleSetup& t, const TileCoverage& cov, PixelRect tile,
                 const float* const (&var)[3], TargetView target, DepthTest test) {
    using S = typename Lanes::S;
    const S& s = lanes.s;
#if HWY_TARGET == HWY_SCALAR  // (one lane: no halves for the double lanes)
    shade_tile<S, false, Blend::alpha>(s, test, t, cov, tile, var, target);
#else
    constexpr int N = S::k_varyings;
    const DF df;
    const DU du;
    const DI di;
    const hn::Half<DF> dfh;
    const hn::Half<DI> dih;
    const hn::Rebind<double, decltype(dfh)> dd;
    using VD = hn::Vec<decltype(dd)>;
    constexpr int L = static_cast<int>(hn::MaxLanes(DF()));

    const LineAaCoverage aa(t);
    int fading[4], fadings = 0;
    for (int k = 0; k < 4; ++k)
        if (aa.per_length[k] > 0) fading[fadings++] = k;

    const VaryingPlanes<N> planes(var);
    const DepthTestLanes depth_test(depth_pass_set(test));
    const MF none = hn::FirstN(df, 0);
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half_f = hn::Set(df, 0.5f);
    TileCoverage rest;  // pixels for the specification (its rows cleared when the first is found)
    bool any_rest = false;

    PixelLanes<L> p{};  // lanes past n keep values of earlier pixels (or zeros): computed, not used
    const auto shade_lanes = [&]() FACET_FORCE_INLINE {
        const MF listed = hn::FirstN(df, static_cast<std::size_t>(p.n));
        const auto xi = hn::Load(di, p.x), yi = hn::Load(di, p.y);
        // LineAaCoverage::at: min(1, each fading edge's value times its 1 / length), in order. The
        // values are integers below 2^41 in double: exact, the int64 values.
        const auto ex = hn::Sub(xi, hn::Set(di, aa.origin.x)), ey = hn::Sub(yi, hn::Set(di, aa.origin.y));
        const VD ex_lo = hn::PromoteTo(dd, hn::LowerHalf(dih, ex)), ex_hi = hn::PromoteTo(dd, hn::UpperHalf(dih, ex));
        const VD ey_lo = hn::PromoteTo(dd, hn::LowerHalf(dih, ey)), ey_hi = hn::PromoteTo(dd, hn::UpperHalf(dih, ey));
        VD d_lo = hn::Set(dd, 1.0), d_hi = d_lo;
        for (int f = 0; f < fadings; ++f) {
            const int k = fading[f];
            const VD e = hn::Set(dd, static_cast<double>(aa.edges.e[k]));
            const VD a = hn::Set(dd, static_cast<double>(aa.edges.a[k])), b = hn::Set(dd, static_cast<double>(aa.edges.b[k]));
            const VD per_length = hn::Set(dd, aa.per_length[k]);
            d_lo = min_into(d_lo, hn::Mul(hn::Add(hn::Add(e, hn::Mul(a, ex_lo)), hn::Mul(b, ey_lo)), per_length));
            d_hi = min_into(d_hi, hn::Mul(hn::Add(hn::Add(e, hn::Mul(a, ex_hi)), hn::Mul(b, ey_hi)), per_length));
        }
        const VF coverage = hn::Combine(df, hn::DemoteTo(dfh, d_hi), hn::DemoteTo(dfh, d_lo));
        const MF active = hn::And(listed, hn::Gt(coverage, zero));  // d > 0 (float(d) > 0 exactly then)

        // depth_at and the depth test (depth_passes_in).
        const VF dx = hn::Sub(hn::Add(hn::ConvertTo(df, xi), half_f), hn::Set(df, t.x0));
        const VF dy = hn::Sub(hn::Add(hn::ConvertTo(df, yi), half_f), hn::Set(df, t.y0));
        const MF drawn = hn::And(active, depth_test.passes(depth_lanes(t, dx, dy), hn::Load(df, p.depth)));
        if (hn::AllFalse(df, drawn)) return;

        // fragment_at's interpolation.
        const VF q = hn::Add(hn::Add(hn::Set(df, t.q0), hn::Mul(hn::Set(df, t.dqdx), dx)), hn::Mul(hn::Set(df, t.dqdy), dy));
        const VF w = hn::Div(one, q);
        const VF b1 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(hn::Set(df, t.dl1dx), dx)), hn::Mul(hn::Set(df, t.dl1dy), dy)), w);
        const VF b2 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(hn::Set(df, t.dl2dx), dx)), hn::Mul(hn::Set(df, t.dl2dy), dy)), w);
        LanesIn<N> in;
        for (int k = 0; k < N; ++k)
            in.v[k] = hn::Add(hn::Add(hn::Set(df, planes.p[k]), hn::Mul(b1, hn::Set(df, planes.p[N + k]))),
                              hn::Mul(b2, hn::Set(df, planes.p[2 * N + k])));
        in.visible = drawn;
        in.scalar = none;
        const ColourLanes c = lanes(in);
        const MF scalar = hn::And(drawn, in.scalar);

        // The blend over the target, alpha times coverage, and to_rgba8.
        const VF a = hn::Mul(blend_alpha(c.a), coverage);
        hn::Store(to_rgba8(blend_over(c.r, c.g, c.b, a, hn::Load(du, p.colour))), du, p.out);
        for (std::uint64_t m = mask_bits(hn::AndNot(scalar, drawn)); m; m &= m - 1) {
            const int l = std::countr_zero(m);
            std::memcpy(target.colour + static_cast<std::size_t>(p.y[l]) * target.stride + p.x[l], &p.out[l], sizeof(Rgba8));
        }
        for (std::uint64_t m = mask_bits(scalar); m; m &= m - 1) {
            if (!any_rest) {
                for (int r = cov.first_row; r <= cov.last_row; ++r) rest.rows[r] = 0;
                rest.first_row = cov.first_row, rest.last_row = cov.last_row;
                any_rest = true;
            }
            const int l = std::countr_zero(m);
            rest.rows[p.y[l] - tile.y0] |= 1ull << (p.x[l] - tile.x0);
        }
    };

    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = tile.y0 + row;
        const Rgba8* colour_row = target.colour + static_cast<std::size_t>(y) * target.stride;
        const float* depth_row = target.depth + static_cast<std::size_t>(y) * target.stride;
        for (; mask; mask &= mask - 1) {
            const int x = tile.x0 + std::countr_zero(mask);
            p.x[p.n] = x, p.y[p.n] = y;
            p.depth[p.n] = depth_row[x];
            std::memcpy(&p.colour[p.n], colour_row + x, sizeof(Rgba8));
            if (++p.n == L) shade_lanes(), p.n = 0;
        }
    }
    if (p.n) shade_lanes();
    if (any_rest) shade_tile<S, false, Blend::alpha>(s, test, t, rest, tile, var, target);
#endif
}

}  // namespace

void BlendLineAaLambertBaseColour(const shaders::LambertBaseColour& s, const TriangleSetup& t, const TileCoverage& cov,
                                  PixelRect tile, const float* const (&var)[3], TargetView target, DepthTest test) {
    BlendLineAa(LambertBaseColourLineLanes{s}, t, cov, tile, var, target, test);
}
void BlendLineAaVertexColour(const shaders::VertexColour& s, const TriangleSetup& t, const TileCoverage& cov,
                             PixelRect tile, const float* const (&var)[3], TargetView target, DepthTest test) {
    BlendLineAa(VertexColourLineLanes{s}, t, cov, tile, var, target, test);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(BlendLineAaLambertBaseColour);
HWY_EXPORT(BlendLineAaVertexColour);

// Records without line_aa (a quad drawn as two triangles, at full coverage) and the "scalar" ISA take
// the specification.
#define FACET_DEFINE_LINE_AA_PASS(S)                                                                          \
    void CompiledLineAaPass<shaders::S>::run(const void* shader, const TriangleSetup& t,                      \
                                             const TileCoverage& coverage, PixelRect tile,                    \
                                             const float* const (&var)[3], TargetView target, DepthTest test, \
                                             std::uint32_t* owner, std::uint32_t id) {                        \
        const auto& s = *static_cast<const shaders::S*>(shader);                                              \
        if (!t.line_aa || use_scalar_kernels())                                                               \
            return shade_tile<shaders::S, false, Blend::alpha>(s, test, t, coverage, tile, var, target, owner, id); \
        HWY_DYNAMIC_DISPATCH(BlendLineAa##S)(s, t, coverage, tile, var, target, test);                        \
    }
FACET_DEFINE_LINE_AA_PASS(LambertBaseColour)
FACET_DEFINE_LINE_AA_PASS(VertexColour)
#undef FACET_DEFINE_LINE_AA_PASS

}  // namespace facet::detail
#endif
