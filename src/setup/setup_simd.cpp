// facet setup: a batch of unclipped triangles set up at once, compiled per ISA by Highway and dispatched
// at run time. One lane per triangle does what setup_triangle (setup.cpp, the specification) does: area,
// culling, orientation, bounds, edge functions with the top-left rule and the attribute planes. The
// lanes then store each triangle's record already in its byte order, four words at a time
// (SetupLanes::unit), so the front end writes a record as eight 16-byte copies instead of 32 scalar
// ones, which were a third of its time.
//
// Why the results are the same bits: the integer quantities (area, bounds, A, B, C) are computed in
// double lanes, where they are exact: snapped coordinates below 2^24 in magnitude (the guard band keeps
// them below 2^22) make every product below 2^50 and every sum below 2^52 (e0's added products A min_x
// and B min_y, with bounds inside the target, are below 2^40), inside the 53-bit mantissa,
// so each double operation gives the integer the scalar code computes, and floor(c / 256) is its
// arithmetic right shift. A batch with a coordinate outside that range goes to setup_triangle instead.
// The attribute planes are the same double operations in the same order as set_planes (no FMA: the
// project builds with -ffp-contract=off and Highway's Mul, Sub and Div round separately), and the
// conversions to float round to nearest as static_cast does. e0 is stored as the two words of an int64,
// split exactly in double (int64_words).
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
using DU = hn::Rebind<std::uint32_t, D>;
using DF = hn::Rebind<float, D>;
using V = hn::Vec<D>;
using VU = hn::Vec<DU>;
using M = hn::Mask<D>;

// Coordinates at or above this magnitude could make an edge constant inexact in double.
constexpr double k_exact_limit = 16777216.0;  // 2^24

struct Corner {
    V x, y, z, q;
};

// Corner k of the group's triangles, every field widened to double (exactly). With `bits`, also z
// and q as stored (the record's z0 and q0 are corner 0's, unchanged).
HWY_INLINE Corner load_corner(const ScreenVertex* v, VU (*bits)[2] = nullptr) {
    const DI di;
    hn::Vec<DI> x, y, z, q;
    hn::LoadInterleaved4(di, reinterpret_cast<const std::int32_t*>(v), x, y, z, q);
    const D d;
    const DF df;
    if (bits) (*bits)[0] = hn::BitCast(DU(), z), (*bits)[1] = hn::BitCast(DU(), q);
    return {hn::PromoteTo(d, x), hn::PromoteTo(d, y), hn::PromoteTo(d, hn::BitCast(df, z)),
            hn::PromoteTo(d, hn::BitCast(df, q))};
}

HWY_INLINE Corner select(M m, const Corner& yes, const Corner& no) {
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

// An integer-valued double lane as the 32-bit word a record stores (|v| < 2^31).
VU word_of_integer(V v) { return hn::BitCast(DU(), hn::DemoteTo(DI(), v)); }
VU word_of_float(V v) { return hn::BitCast(DU(), hn::DemoteTo(DF(), v)); }

// The low and high words of an integer-valued double lane as an int64 (|v| < 2^52, two's
// complement, little-endian): high = floor(v / 2^32) and low = v - high 2^32 in [0, 2^32), all exact.
HWY_INLINE void int64_words(V v, VU& low, VU& high) {
    const D d;
    const V h = hn::Floor(hn::Mul(v, hn::Set(d, 1.0 / 4294967296.0)));
    const V l = hn::Sub(hn::Sub(v, hn::Mul(h, hn::Set(d, 4294967296.0))), hn::Set(d, 2147483648.0));
    low = hn::Xor(word_of_integer(l), hn::Set(DU(), 0x80000000u));  // l + 2^31, modulo 2^32
    high = word_of_integer(h);
}

// A mask of double lanes as one of 32-bit lanes (RebindMask needs lanes of one size).
hn::Mask<DU> word_mask(M m) { return hn::MaskFromVec(word_of_integer(hn::IfThenElseZero(m, hn::Set(D(), -1.0)))); }

// first_centre and last_centre of setup.cpp: floor(v / 256) is the arithmetic shift by 8.
V floor_div_256(V v) { return hn::Floor(hn::Mul(v, hn::Set(D(), 1.0 / k_subpixel_one))); }

struct Edge {
    VU a, b, e0_low, e0_high;
    M small;  // as edges_fit_32_bits tests each edge
};

// Edge a->b as set_edge: A, B, c = floor((C + bias + 128 (A + B)) / 256) and e0 = c + A min_x + B min_y,
// all exact integers.
HWY_INLINE Edge set_edge(const Corner& a, const Corner& b, V min_x, V min_y) {
    const D d;
    const V zero = hn::Zero(d);
    const V A = hn::Sub(a.y, b.y), B = hn::Sub(b.x, a.x);
    const V C = hn::Neg(hn::Add(hn::Mul(A, a.x), hn::Mul(B, a.y)));
    const M top_left = hn::Or(hn::Gt(A, zero), hn::And(hn::Eq(A, zero), hn::Gt(B, zero)));
    const V bias = hn::IfThenZeroElse(top_left, hn::Set(d, -1.0));
    const V c = hn::Add(hn::Add(C, bias), hn::Mul(hn::Set(d, k_subpixel_one / 2), hn::Add(A, B)));
    const V e0 = hn::Add(hn::Add(floor_div_256(c), hn::Mul(A, min_x)), hn::Mul(B, min_y));
    Edge edge;
    edge.a = word_of_integer(A);
    edge.b = word_of_integer(B);
    int64_words(e0, edge.e0_low, edge.e0_high);
    const V step_limit = hn::Set(d, 1 << 15);
    edge.small = hn::And(hn::And(hn::Le(hn::Abs(A), step_limit), hn::Le(hn::Abs(B), step_limit)),
                         hn::Lt(hn::Abs(e0), hn::Set(d, 1 << 30)));
    return edge;
}

struct Plane {
    VU dfdx, dfdy;
};

// One attribute plane as set_planes computes it, from the values f0, f1, f2 at the three vertices.
HWY_INLINE Plane set_plane(V f0, V f1, V f2, V x1, V x2, V y1, V y2, V inv_area) {
    const V d1 = hn::Sub(f1, f0), d2 = hn::Sub(f2, f0);
    const V dfdx = hn::Mul(hn::Sub(hn::Mul(d1, y2), hn::Mul(d2, y1)), inv_area);
    const V dfdy = hn::Mul(hn::Sub(hn::Mul(d2, x1), hn::Mul(d1, x2)), inv_area);
    return {word_of_float(dfdx), word_of_float(dfdy)};
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

// Words 4g..4g+3 of the records of triangles i0.. (see SetupLanes).
HWY_INLINE void store_unit(SetupLanes& out, int g, int i0, VU w0, VU w1, VU w2, VU w3) {
    hn::StoreInterleaved4(w0, w1, w2, w3, DU(), out.unit[g][i0].word);
}

// Returns false, having written nothing useful, when a coordinate is too large for exact doubles.
bool SetupLanesOf(const SetupBatch& batch, const FrontEndParams& p, SetupLanes& out) {
    const D d;
    const DU du;
    const int lanes = static_cast<int>(hn::Lanes(d));
    const V scissor_x0 = hn::Set(d, p.scissor.x0), scissor_y0 = hn::Set(d, p.scissor.y0);
    const V scissor_x1 = hn::Set(d, p.scissor.x1 - 1), scissor_y1 = hn::Set(d, p.scissor.y1 - 1);
    const V half = hn::Set(d, k_subpixel_one / 2);
    const bool ccw_front = p.state.front_face == FrontFace::ccw;
    out.keep = out.culled = 0;  // the caller may reuse `out` batch after batch
    for (int i0 = 0; i0 < batch.count; i0 += lanes) {
        VU zq0[2];  // corner 0's z and q as stored
        const Corner s0 = load_corner(batch.v[0] + i0, &zq0), s1 = load_corner(batch.v[1] + i0),
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

        // Orient so that the inside of every edge is where its function is positive.
        const Corner v1 = select(flip, s2, s1), v2 = select(flip, s1, s2);
        const Edge e[3] = {set_edge(s0, v1, min_x, min_y), set_edge(v1, v2, min_x, min_y),
                           set_edge(v2, s0, min_x, min_y)};
        // The attribute planes as set_planes.
        const V x1 = hn::Sub(v1.x, s0.x), x2 = hn::Sub(v2.x, s0.x);
        const V y1 = hn::Sub(v1.y, s0.y), y2 = hn::Sub(v2.y, s0.y);
        const V inv_area = hn::Div(hn::Set(d, k_subpixel_one), hn::Abs(signed_area));
        const V zero = hn::Zero(d);
        const Plane z = set_plane(s0.z, v1.z, v2.z, x1, x2, y1, y2, inv_area);
        const Plane q = set_plane(s0.q, v1.q, v2.q, x1, x2, y1, y2, inv_area);
        const Plane l1 = set_plane(zero, v1.q, zero, x1, x2, y1, y2, inv_area);
        const Plane l2 = set_plane(zero, zero, v2.q, x1, x2, y1, y2, inv_area);
        const V scale = hn::Set(d, 1.0 / k_subpixel_one);

        // The vertices' varyings in the record's winding; then front_facing and small_edges, a byte each.
        const auto flip_u = word_mask(flip);
        const VU r0 = hn::LoadU(du, batch.ref[0] + i0), r1 = hn::LoadU(du, batch.ref[1] + i0),
                 r2 = hn::LoadU(du, batch.ref[2] + i0);
        const M small = hn::And(hn::And(e[0].small, e[1].small), e[2].small);
        const VU flags = hn::Or(hn::IfThenElseZero(word_mask(front), hn::Set(du, 1u)),
                                hn::IfThenElseZero(word_mask(small), hn::Set(du, 1u << 8)));

        // The record's 32 words in order (TriangleSetup).
        store_unit(out, 0, i0, e[0].a, e[1].a, e[2].a, e[0].b);
        store_unit(out, 1, i0, e[1].b, e[2].b, e[0].e0_low, e[0].e0_high);
        store_unit(out, 2, i0, e[1].e0_low, e[1].e0_high, e[2].e0_low, e[2].e0_high);
        store_unit(out, 3, i0, word_of_integer(min_x), word_of_integer(min_y), word_of_integer(max_x),
                   word_of_integer(max_y));
        store_unit(out, 4, i0, word_of_float(hn::Mul(s0.x, scale)), word_of_float(hn::Mul(s0.y, scale)), zq0[0],
                   z.dfdx);
        store_unit(out, 5, i0, z.dfdy, zq0[1], q.dfdx, q.dfdy);
        store_unit(out, 6, i0, l1.dfdx, l1.dfdy, l2.dfdx, l2.dfdy);
        store_unit(out, 7, i0, r0, hn::IfThenElse(flip_u, r2, r1), hn::IfThenElse(flip_u, r1, r2), flags);
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

HWY_EXPORT(SetupLanesOf);

bool setup_lanes(const SetupBatch& batch, const FrontEndParams& params, SetupLanes& lanes) {
    return !use_scalar_kernels() && HWY_DYNAMIC_DISPATCH(SetupLanesOf)(batch, params, lanes);
}

BatchSetupCounts setup_triangles(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out) {
    SetupLanes lanes;
    if (!setup_lanes(batch, params, lanes)) return setup_one_by_one(batch, params, out);
    int written = 0;
    for (std::uint32_t keep = lanes.keep; keep != 0; keep &= keep - 1)
        write_record(lanes, std::countr_zero(keep), out[written++]);
    return {written, std::popcount(lanes.culled)};
}

}  // namespace facet::detail
#endif
