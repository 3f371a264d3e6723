// facet geometry: the projection pass over a block of vertices (project_vertices, project.hpp) as a
// SIMD kernel, compiled per ISA by Highway and dispatched at run time. One lane per vertex does what
// project_vertex does (the specification, project.cpp): the finite check, the outcode's seven
// plane tests and, for vertices inside every plane, the division by w, the viewport and the snap.
// The same float operations in the same order (no FMA: -ffp-contract=off, and Highway's Mul and
// Add round separately), 1/w as a true division, and the snap's rounding to nearest even as
// std::lrint's in the default rounding mode: the same bytes on every ISA.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "geometry/project_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <limits>

#include "geometry/clip.hpp"
#include "geometry/project.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Vertices [first, end): whole vectors here, the rest (fewer than a vector) by project_vertex.
void ProjectVertices(const Vec4* pos, ClipVertices& vertices, std::size_t first, std::size_t end, const FrontEndParams& p) {
    const hn::ScalableTag<float> df;
    const hn::RebindToSigned<decltype(df)> di;
    const hn::Rebind<std::uint8_t, decltype(di)> d8;
    using VF = hn::Vec<decltype(df)>;
    const std::size_t lanes = hn::Lanes(df);
    const GuardBand g = guard_band(p);
    const VF gx = hn::Set(df, g.gx), gy = hn::Set(df, g.gy), zero = hn::Zero(df), one = hn::Set(df, 1.0f);
    const VF infinity = hn::Set(df, std::numeric_limits<float>::infinity());
    const VF min_w = hn::Set(df, k_min_clip_w);
    const VF vp_x = hn::Set(df, p.vp_x), vp_y = hn::Set(df, p.vp_y);
    const VF half_w = hn::Set(df, p.vp_w * 0.5f), half_h = hn::Set(df, p.vp_h * 0.5f);
    const VF snap = hn::Set(df, static_cast<float>(k_subpixel_one));
    std::size_t i = first;
    for (; i + lanes <= end; i += lanes) {
        VF x, y, z, w;
        hn::LoadInterleaved4(df, reinterpret_cast<const float*>(pos + (i - first)), x, y, z, w);
        // Finite: |v| < infinity is false for NaN and for either infinity.
        const auto finite = hn::And(hn::And(hn::Lt(hn::Abs(x), infinity), hn::Lt(hn::Abs(y), infinity)),
                                    hn::And(hn::Lt(hn::Abs(z), infinity), hn::Lt(hn::Abs(w), infinity)));
        // The planes in outcode's order: bit p where plane p's distance is < 0.
        const VF distance[k_clip_plane_count] = {hn::Sub(w, min_w),          z,
                                                 hn::Sub(w, z),              hn::Add(x, hn::Mul(gx, w)),
                                                 hn::Sub(hn::Mul(gx, w), x), hn::Add(y, hn::Mul(gy, w)),
                                                 hn::Sub(hn::Mul(gy, w), y)};
        auto code = hn::Zero(di);
        for (int plane = 0; plane < k_clip_plane_count; ++plane)
            code = hn::Or(code, hn::IfThenElseZero(hn::RebindMask(di, hn::Lt(distance[plane], zero)),
                                                   hn::Set(di, 1 << plane)));
        code = hn::IfThenElse(hn::RebindMask(di, finite), code, hn::Set(di, k_outcode_invalid));
        hn::StoreU(hn::DemoteTo(d8, code), d8, vertices.outcode.data() + i);
        // project(): every lane computes, and lanes outside a plane store zeros (never read).
        const VF q = hn::Div(one, w);
        const VF sx = hn::Add(vp_x, hn::Mul(hn::Add(hn::Mul(x, q), one), half_w));
        const VF sy = hn::Add(vp_y, hn::Mul(hn::Sub(one, hn::Mul(y, q)), half_h));
        VF sz = hn::Mul(z, q);
        sz = hn::IfThenElse(hn::Lt(sz, zero), zero, hn::IfThenElse(hn::Lt(one, sz), one, sz));  // std::clamp
        const auto inside = hn::RebindMask(df, hn::Eq(code, hn::Zero(di)));
        const auto ix = hn::IfThenElseZero(hn::RebindMask(di, inside), hn::NearestInt(hn::Mul(sx, snap)));
        const auto iy = hn::IfThenElseZero(hn::RebindMask(di, inside), hn::NearestInt(hn::Mul(sy, snap)));
        hn::StoreInterleaved4(hn::BitCast(df, ix), hn::BitCast(df, iy), hn::IfThenElseZero(inside, sz),
                              hn::IfThenElseZero(inside, q), df, reinterpret_cast<float*>(vertices.screen.data() + i));
    }
    for (; i < end; ++i) project_vertex(pos[i - first], vertices, i, g, p);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(ProjectVertices);

void project_vertices(const Vec4* pos, ClipVertices& vertices, std::size_t first, std::size_t end,
                      const FrontEndParams& params) {
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(ProjectVertices)(pos, vertices, first, end, params);
    const GuardBand guard = guard_band(params);
    for (std::size_t i = first; i < end; ++i) project_vertex(pos[i - first], vertices, i, guard, params);
}

}  // namespace facet::detail
#endif
