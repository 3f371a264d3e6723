// facet setup: a batch of unclipped triangles set up at once, compiled per ISA by Highway and dispatched
// at run time. One lane per triangle does what setup_triangle (setup.cpp, the specification) does: area,
// culling, orientation, bounds, edge functions with the top-left rule and the attribute planes; a scalar
// loop then writes the records of the lanes that survive, in batch order.
//
// Why the results are the same bits: the integer quantities (area, bounds, A, B, C) are computed in
// double lanes, where they are exact: snapped coordinates below 2^24 in magnitude (the guard band keeps
// them below 2^22) make every product below 2^50 and every sum below 2^52 (e0's added products A min_x
// and B min_y, with bounds inside the target, are below 2^40), inside the 53-bit mantissa,
// so each double operation gives the integer the scalar code computes, and floor(c / 256) is its
// arithmetic right shift. A batch with a coordinate outside that range goes to setup_triangle instead.
// The attribute planes are the same double operations in the same order as set_planes (no FMA: the
// project builds with -ffp-contract=off and Highway's Mul, Sub and Div round separately), and the
// conversions to float round to nearest as static_cast does.
#include <cstdint>

#include "setup/setup.hpp"


#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "setup/setup_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using DI = hn::Rebind<std::int32_t, D>;
using DF = hn::Rebind<float, D>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// Coordinates at or above this magnitude could make an edge constant inexact in double.
constexpr double k_exact_limit = 16777216.0;  // 2^24

struct Corner {
    V x, y, z, q;
};

// Corner k of the group's triangles, every field widened to double (exactly).
Corner load_corner(const ScreenVertex* v) {
    const DI di;
    hn::Vec<DI> x, y, z, q;
    hn::LoadInterleaved4(di, reinterpret_cast<const std::int32_t*>(v), x, y, z, q);
    const D d;
    const DF df;
    return {hn::PromoteTo(d, x), hn::PromoteTo(d, y), hn::PromoteTo(d, hn::BitCast(df, z)),
            hn::PromoteTo(d, hn::BitCast(df, q))};
}

Corner select(M m, const Corner& yes, const Corner& no) {
    return {hn::IfThenElse(m, yes.x, no.x), hn::IfThenElse(m, yes.y, no.y), hn::IfThenElse(m, yes.z, no.z),
            hn::IfThenElse(m, yes.q, no.q)};
}

bool coordinates_exact(const Corner& a, const Corner& b, const Corner& c) {
    const D d;
    const V m = hn::Max(hn::Max(hn::Max(hn::Abs(a.x), hn::Abs(a.y)), hn::Max(hn::Abs(b.x), hn::Abs(b.y))),
                        hn::Max(hn::Abs(c.x), hn::Abs(c.y)));
    return hn::AllTrue(d, hn::Lt(m, hn::Set(d, k_exact_limit)));
}

std::uint32_t mask_bits(M m) {
    std::uint8_t bits[8] = {};
    hn::StoreMaskBits(D(), m, bits);
    return bits[0];  // at most 8 double lanes
}

// first_centre and last_centre of setup.cpp: floor(v / 256) is the arithmetic shift by 8.
V floor_div_256(V v) { return hn::Floor(hn::Mul(v, hn::Set(D(), 1.0 / k_subpixel_one))); }

// Edge a->b as set_edge: A, B, c = floor((C + bias + 128 (A + B)) / 256) and e0 = c + A min_x + B min_y,
// all exact integers. Returns the lanes where the edge is small, as edges_fit_32_bits tests each.
M set_edges(const Corner& a, const Corner& b, V min_x, V min_y, int e, int i0, SetupLanes& out) {
    const D d;
    const DI di;
    const V zero = hn::Zero(d);
    const V A = hn::Sub(a.y, b.y), B = hn::Sub(b.x, a.x);
    const V C = hn::Neg(hn::Add(hn::Mul(A, a.x), hn::Mul(B, a.y)));
    const M top_left = hn::Or(hn::Gt(A, zero), hn::And(hn::Eq(A, zero), hn::Gt(B, zero)));
    const V bias = hn::IfThenZeroElse(top_left, hn::Set(d, -1.0));
    const V c = hn::Add(hn::Add(C, bias), hn::Mul(hn::Set(d, k_subpixel_one / 2), hn::Add(A, B)));
    hn::StoreU(hn::DemoteTo(di, A), di, out.a[e] + i0);
    hn::StoreU(hn::DemoteTo(di, B), di, out.b[e] + i0);
    const V e0 = hn::Add(hn::Add(floor_div_256(c), hn::Mul(A, min_x)), hn::Mul(B, min_y));
    hn::StoreU(e0, d, out.e0[e] + i0);
    const V step_limit = hn::Set(d, 1 << 15);
    return hn::And(hn::And(hn::Le(hn::Abs(A), step_limit), hn::Le(hn::Abs(B), step_limit)),
                   hn::Lt(hn::Abs(e0), hn::Set(d, 1 << 30)));
}

// One attribute plane as set_planes computes it, from the values f0, f1, f2 at the three vertices.
void set_plane(V f0, V f1, V f2, V x1, V x2, V y1, V y2, V inv_area, int k, int i0, SetupLanes& out) {
    const DF df;
    const V d1 = hn::Sub(f1, f0), d2 = hn::Sub(f2, f0);
    const V dfdx = hn::Mul(hn::Sub(hn::Mul(d1, y2), hn::Mul(d2, y1)), inv_area);
    const V dfdy = hn::Mul(hn::Sub(hn::Mul(d2, x1), hn::Mul(d1, x2)), inv_area);
    hn::StoreU(hn::DemoteTo(df, dfdx), df, out.dfdx[k] + i0);
    hn::StoreU(hn::DemoteTo(df, dfdy), df, out.dfdy[k] + i0);
}

void set_planes(const Corner& v0, const Corner& v1, const Corner& v2, V area, int i0, SetupLanes& out) {
    const D d;
    const DF df;
    const V x1 = hn::Sub(v1.x, v0.x), x2 = hn::Sub(v2.x, v0.x);
    const V y1 = hn::Sub(v1.y, v0.y), y2 = hn::Sub(v2.y, v0.y);
    const V inv_area = hn::Div(hn::Set(d, k_subpixel_one), area);
    const V zero = hn::Zero(d);
    set_plane(v0.z, v1.z, v2.z, x1, x2, y1, y2, inv_area, 0, i0, out);
    set_plane(v0.q, v1.q, v2.q, x1, x2, y1, y2, inv_area, 1, i0, out);
    set_plane(zero, v1.q, zero, x1, x2, y1, y2, inv_area, 2, i0, out);
    set_plane(zero, zero, v2.q, x1, x2, y1, y2, inv_area, 3, i0, out);
    const V scale = hn::Set(d, 1.0 / k_subpixel_one);
    hn::StoreU(hn::DemoteTo(df, hn::Mul(v0.x, scale)), df, out.x0 + i0);
    hn::StoreU(hn::DemoteTo(df, hn::Mul(v0.y, scale)), df, out.y0 + i0);
}

// Which lanes the draw state culls, given the signed area (see setup_triangle).
M culled_lanes(V signed_area, M front, const FrontEndParams& p) {
    const D d;
    const M zero_area = hn::Eq(signed_area, hn::Zero(d));
    switch (p.state.cull) {
        case CullMode::back: return hn::Or(zero_area, hn::Not(front));
        case CullMode::front: return hn::Or(zero_area, front);
        case CullMode::none: break;
    }
    return zero_area;
}

// Returns false, having written nothing useful, when a coordinate is too large for exact doubles.
bool SetupLanesOf(const SetupBatch& batch, const FrontEndParams& p, SetupLanes& out) {
    const D d;
    const DI di;
    const int lanes = static_cast<int>(hn::Lanes(d));
    const V scissor_x0 = hn::Set(d, p.scissor.x0), scissor_y0 = hn::Set(d, p.scissor.y0);
    const V scissor_x1 = hn::Set(d, p.scissor.x1 - 1), scissor_y1 = hn::Set(d, p.scissor.y1 - 1);
    const V half = hn::Set(d, k_subpixel_one / 2);
    const bool ccw_front = p.state.front_face == FrontFace::ccw;
    out.keep = out.culled = out.flip = out.front = out.small_edges = 0;  // the caller may reuse `out` batch after batch
    for (int i0 = 0; i0 < batch.count; i0 += lanes) {
        const Corner s0 = load_corner(batch.v[0] + i0), s1 = load_corner(batch.v[1] + i0),
                     s2 = load_corner(batch.v[2] + i0);
        if (!coordinates_exact(s0, s1, s2)) return false;
        const V signed_area = hn::Sub(hn::Mul(hn::Sub(s1.x, s0.x), hn::Sub(s2.y, s0.y)),
                                      hn::Mul(hn::Sub(s2.x, s0.x), hn::Sub(s1.y, s0.y)));
        const M flip = hn::Lt(signed_area, hn::Zero(d));  // viewer sees it counter-clockwise
        const M front = ccw_front ? flip : hn::Not(flip);
        const M culled = hn::And(culled_lanes(signed_area, front, p), hn::FirstN(d, batch.count - i0));

        const V lo_x = hn::Min(s0.x, hn::Min(s1.x, s2.x)), hi_x = hn::Max(s0.x, hn::Max(s1.x, s2.x));
        const V lo_y = hn::Min(s0.y, hn::Min(s1.y, s2.y)), hi_y = hn::Max(s0.y, hn::Max(s1.y, s2.y));
        const V min_x = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_x))), scissor_x0);
        const V max_x = hn::Min(floor_div_256(hn::Sub(hi_x, half)), scissor_x1);
        const V min_y = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_y))), scissor_y0);
        const V max_y = hn::Min(floor_div_256(hn::Sub(hi_y, half)), scissor_y1);
        const M empty = hn::Or(hn::Gt(min_x, max_x), hn::Gt(min_y, max_y));
        const M keep = hn::AndNot(hn::Or(culled, empty), hn::FirstN(d, batch.count - i0));

        out.culled |= mask_bits(culled) << i0;
        if (hn::AllFalse(d, keep)) continue;
        out.keep |= mask_bits(keep) << i0;
        out.flip |= mask_bits(flip) << i0;
        out.front |= mask_bits(front) << i0;
        hn::StoreU(hn::DemoteTo(di, min_x), di, out.min_x + i0);
        hn::StoreU(hn::DemoteTo(di, max_x), di, out.max_x + i0);
        hn::StoreU(hn::DemoteTo(di, min_y), di, out.min_y + i0);
        hn::StoreU(hn::DemoteTo(di, max_y), di, out.max_y + i0);

        // Orient so that the inside of every edge is where its function is positive.
        const Corner v1 = select(flip, s2, s1), v2 = select(flip, s1, s2);
        const M small = hn::And(hn::And(set_edges(s0, v1, min_x, min_y, 0, i0, out), set_edges(v1, v2, min_x, min_y, 1, i0, out)),
                                set_edges(v2, s0, min_x, min_y, 2, i0, out));
        out.small_edges |= mask_bits(small) << i0;
        set_planes(s0, v1, v2, hn::Abs(signed_area), i0, out);
    }
    return true;
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <bit>

#include "simd/isa.hpp"

namespace facet::detail {

BatchSetupCounts setup_one_by_one(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out) {
    BatchSetupCounts counts{0, 0};
    for (int i = 0; i < batch.count; ++i) {
        const ScreenVertex v[3] = {batch.v[0][i], batch.v[1][i], batch.v[2][i]};
        const std::uint32_t ref[3] = {batch.ref[0][i], batch.ref[1][i], batch.ref[2][i]};
        switch (setup_triangle(v, ref, params, out[counts.written])) {
            case SetupResult::ok: ++counts.written; break;
            case SetupResult::culled: ++counts.culled; break;
            case SetupResult::empty: break;
        }
    }
    return counts;
}

// The record of batch triangle i, field by field as setup_triangle writes it. Plain copies: this file
// is compiled without GCC's SLP vectoriser (src/CMakeLists.txt), whose shuffles into wider stores
// made the writer 30% slower.
void write_record(const SetupBatch& batch, const SetupLanes& lanes, int i, TriangleSetup& t) {
    for (int e = 0; e < 3; ++e) {
        t.a[e] = lanes.a[e][i];
        t.b[e] = lanes.b[e][i];
        t.e0[e] = static_cast<std::int64_t>(lanes.e0[e][i]);
    }
    t.min_x = lanes.min_x[i], t.max_x = lanes.max_x[i];
    t.min_y = lanes.min_y[i], t.max_y = lanes.max_y[i];
    t.x0 = lanes.x0[i], t.y0 = lanes.y0[i];
    t.z0 = batch.v[0][i].z, t.dzdx = lanes.dfdx[0][i], t.dzdy = lanes.dfdy[0][i];
    t.q0 = batch.v[0][i].q, t.dqdx = lanes.dfdx[1][i], t.dqdy = lanes.dfdy[1][i];
    t.dl1dx = lanes.dfdx[2][i], t.dl1dy = lanes.dfdy[2][i];
    t.dl2dx = lanes.dfdx[3][i], t.dl2dy = lanes.dfdy[3][i];
    const std::uint32_t bit = 1u << i;
    const bool flip = (lanes.flip & bit) != 0;
    t.vertex[0] = batch.ref[0][i];
    t.vertex[1] = batch.ref[flip ? 2 : 1][i];
    t.vertex[2] = batch.ref[flip ? 1 : 2][i];
    // Tested in a register: a bit extracted into the record's byte made the compiler mask it in
    // memory, a read of a record line not yet in the cache (40% of this function's time).
    t.front_facing = (lanes.front & bit) != 0;
    t.small_edges = (lanes.small_edges & bit) != 0;
}

HWY_EXPORT(SetupLanesOf);

bool setup_lanes(const SetupBatch& batch, const FrontEndParams& params, SetupLanes& lanes) {
    return !use_scalar_kernels() && HWY_DYNAMIC_DISPATCH(SetupLanesOf)(batch, params, lanes);
}

BatchSetupCounts setup_triangles(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out) {
    SetupLanes lanes;
    if (!setup_lanes(batch, params, lanes)) return setup_one_by_one(batch, params, out);
    int written = 0;
    for (std::uint32_t keep = lanes.keep; keep != 0; keep &= keep - 1)
        write_record(batch, lanes, std::countr_zero(keep), out[written++]);
    return {written, std::popcount(lanes.culled)};
}

}  // namespace facet::detail
#endif
