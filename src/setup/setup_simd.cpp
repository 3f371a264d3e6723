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
// Batches of triangles under 64 pixels across (nearly all of a dense mesh's) take a shorter path:
// the integers in 32-bit lanes, twice as many per vector, exact for the reasons at SetUpGroupIn32Bits.
// The attribute planes are the same double operations in the same order as set_planes (no FMA: the
// project builds with -ffp-contract=off and Highway's Mul, Sub and Div round separately), and the
// conversions to float round to nearest as static_cast does. e0 is stored as the two words of an int64,
// split exactly in double (int64_words).
#include <bit>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "setup/setup.hpp"


#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "setup/setup_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "setup/record_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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

// The low and high words of an integer-valued double lane as an int64 (|v| < 2^52, two's
// complement, little-endian): high = floor(v / 2^32) and low = v - high 2^32 in [0, 2^32), all exact.
HWY_INLINE void int64_words(V v, VU& low, VU& high) {
    const D d;
    const V h = hn::Floor(hn::Mul(v, hn::Set(d, 1.0 / 4294967296.0)));
    const V l = hn::Sub(hn::Sub(v, hn::Mul(h, hn::Set(d, 4294967296.0))), hn::Set(d, 2147483648.0));
    low = hn::Xor(word_of_integer(l), hn::Set(DU(), 0x80000000u));  // l + 2^31, modulo 2^32
    high = word_of_integer(h);
}

struct Edge {
    VU a, b, e0_low, e0_high;
    M small;     // as edges_fit_32_bits tests each edge
    V A, B, e0;  // a, b and e0 as doubles
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
    edge.A = A, edge.B = B, edge.e0 = e0;
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

// The four planes of set_planes: depth, q, and the barycentrics b1 q and b2 q (q1 at vertex 1 and
// q2 at vertex 2, 0 elsewhere), from the corners' depths and q and their offsets from corner 0.
struct Planes {
    Plane z, q, l1, l2;
};
HWY_INLINE Planes set_planes(V z0, V z1, V z2, V q0, V q1, V q2, V x1, V x2, V y1, V y2, V inv_area) {
    const V zero = hn::Zero(D());
    return {set_plane(z0, z1, z2, x1, x2, y1, y2, inv_area), set_plane(q0, q1, q2, x1, x2, y1, y2, inv_area),
            set_plane(zero, q1, zero, x1, x2, y1, y2, inv_area), set_plane(zero, zero, q2, x1, x2, y1, y2, inv_area)};
}

// Which lanes the draw state culls, given the signed area (see setup_triangle): double or int32 lanes.
template <class Tag>
hn::Mask<Tag> culled_lanes(Tag t, hn::Vec<Tag> signed_area, hn::Mask<Tag> front, const FrontEndParams& p) {
    const hn::Mask<Tag> zero_area = hn::Eq(signed_area, hn::Zero(t));
    switch (p.state.cull) {
        case CullMode::back: return hn::Or(zero_area, hn::Not(front));
        case CullMode::front: return hn::Or(zero_area, front);
        case CullMode::none: break;
    }
    return zero_area;
}

// SetupLanes::tile of lanes with inclusive pixel bounds min..max (int32 lanes, non-negative where
// kept): bounds share their tile exactly when they agree above the tile's bits.
template <class Tag>
HWY_INLINE void store_tiles(Tag t, hn::Vec<Tag> min_x, hn::Vec<Tag> min_y, hn::Vec<Tag> max_x, hn::Vec<Tag> max_y,
                            const FrontEndParams& p, std::int32_t* out) {
    const int shift = std::countr_zero(static_cast<unsigned>(p.tile_size));
    const auto spread = hn::ShiftRightSame(hn::Or(hn::Xor(min_x, max_x), hn::Xor(min_y, max_y)), shift);
    const auto tile = hn::Add(hn::Mul(hn::ShiftRightSame(min_y, shift), hn::Set(t, p.tiles_x)), hn::ShiftRightSame(min_x, shift));
    hn::StoreU(hn::IfThenElse(hn::Eq(spread, hn::Zero(t)), tile, hn::Set(t, -1)), t, out);
}

// Lanes whose bounds are within k_small_bounds pixels on both axes (w, h: max - min) and whose
// triangle covers none of their centres, as covers_no_centre_of_small_bounds tests them: each edge
// from its value at the bounds' corner (e0) by its steps per column (a) and row (b), exactly in
// either kind of lane (int32: every value below 2^22; double: integers below 2^53). A step past the
// bounds is a step of 0, so those positions repeat one inside them. The sign bits of the three
// edges ORed say "outside", ANDed over the positions "outside at all of them"; double lanes compare
// for the sign instead (a sum there can be -0).
template <class Tag>
HWY_INLINE hn::Mask<Tag> small_and_empty(Tag t, const hn::Vec<Tag> (&e0)[3], const hn::Vec<Tag> (&a)[3],
                                         const hn::Vec<Tag> (&b)[3], hn::Vec<Tag> w, hn::Vec<Tag> h) {
    static_assert(k_small_bounds == 3, "two steps per axis");
    using VT = hn::Vec<Tag>;
    constexpr bool k_integer = std::is_integral_v<hn::TFromD<Tag>>;
    const auto negative = [](VT v) {  // sign bit set where v < 0
        if constexpr (std::is_integral_v<hn::TFromD<Tag>>) return v;
        else return hn::VecFromMask(Tag(), hn::Lt(v, hn::Zero(Tag())));
    };
    const VT zero = hn::Zero(t), one = hn::Set(t, 1);
    const auto w1 = hn::Gt(w, zero), w2 = hn::Gt(w, one), h1 = hn::Gt(h, zero), h2 = hn::Gt(h, one);
    VT row[3] = {e0[0], e0[1], e0[2]}, outside_everywhere{};
    for (int y = 0; y < k_small_bounds; ++y) {
        if (y > 0)
            for (int k = 0; k < 3; ++k) row[k] = hn::Add(row[k], hn::IfThenElseZero(y == 1 ? h1 : h2, b[k]));
        VT e[3] = {row[0], row[1], row[2]};
        for (int x = 0; x < k_small_bounds; ++x) {
            if (x > 0)
                for (int k = 0; k < 3; ++k) e[k] = hn::Add(e[k], hn::IfThenElseZero(x == 1 ? w1 : w2, a[k]));
            const VT outside = hn::Or(hn::Or(negative(e[0]), negative(e[1])), negative(e[2]));
            outside_everywhere = x == 0 && y == 0 ? outside : hn::And(outside_everywhere, outside);
        }
    }
    if constexpr (k_integer) outside_everywhere = hn::ShiftRight<sizeof(hn::TFromD<Tag>) * 8 - 1>(outside_everywhere);
    const VT limit = hn::Set(t, k_small_bounds);
    return hn::And(hn::MaskFromVec(outside_everywhere), hn::And(hn::Lt(w, limit), hn::Lt(h, limit)));
}

// Triangles i0 .. i0 + Lanes(D) - 1 of the batch in double lanes, exact for every coordinate below
// 2^24. False, having written nothing useful, when a coordinate is larger.
bool SetUpGroupInDouble(const SetupBatch& batch, const FrontEndParams& p, SetupLanes& out, int i0) {
    const D d;
    const DU du;
    const V scissor_x0 = hn::Set(d, p.scissor.x0), scissor_y0 = hn::Set(d, p.scissor.y0);
    const V scissor_x1 = hn::Set(d, p.scissor.x1 - 1), scissor_y1 = hn::Set(d, p.scissor.y1 - 1);
    const V half = hn::Set(d, k_subpixel_one / 2);
    const bool ccw_front = p.state.front_face == FrontFace::ccw;
    VU zq0[2];  // corner 0's z and q as stored
    const Corner s0 = load_corner(batch.v[0] + i0, &zq0), s1 = load_corner(batch.v[1] + i0),
                 s2 = load_corner(batch.v[2] + i0);
    if (!coordinates_exact(s0, s1, s2)) return false;
    const V signed_area = hn::Sub(hn::Mul(hn::Sub(s1.x, s0.x), hn::Sub(s2.y, s0.y)),
                                  hn::Mul(hn::Sub(s2.x, s0.x), hn::Sub(s1.y, s0.y)));
    const M flip = hn::Lt(signed_area, hn::Zero(d));  // viewer sees it counter-clockwise
    const M front = ccw_front ? flip : hn::Not(flip);
    const M culled = hn::And(culled_lanes(d, signed_area, front, p), hn::FirstN(d, batch.count - i0));

    const V lo_x = hn::Min(s0.x, hn::Min(s1.x, s2.x)), hi_x = hn::Max(s0.x, hn::Max(s1.x, s2.x));
    const V lo_y = hn::Min(s0.y, hn::Min(s1.y, s2.y)), hi_y = hn::Max(s0.y, hn::Max(s1.y, s2.y));
    const V min_x = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_x))), scissor_x0);
    const V max_x = hn::Min(floor_div_256(hn::Sub(hi_x, half)), scissor_x1);
    const V min_y = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_y))), scissor_y0);
    const V max_y = hn::Min(floor_div_256(hn::Sub(hi_y, half)), scissor_y1);
    const M empty = hn::Or(hn::Gt(min_x, max_x), hn::Gt(min_y, max_y));
    const M keep = hn::AndNot(hn::Or(culled, empty), hn::FirstN(d, batch.count - i0));

    out.culled |= mask_bits(culled) << i0;
    if (hn::AllFalse(d, keep)) return true;

    // Orient so that the inside of every edge is where its function is positive.
    const Corner v1 = select(flip, s2, s1), v2 = select(flip, s1, s2);
    const Edge e[3] = {set_edge(s0, v1, min_x, min_y), set_edge(v1, v2, min_x, min_y),
                       set_edge(v2, s0, min_x, min_y)};
    const V e0s[3] = {e[0].e0, e[1].e0, e[2].e0}, as[3] = {e[0].A, e[1].A, e[2].A}, bs[3] = {e[0].B, e[1].B, e[2].B};
    out.keep |= mask_bits(hn::AndNot(small_and_empty(d, e0s, as, bs, hn::Sub(max_x, min_x), hn::Sub(max_y, min_y)), keep))
                << i0;
    // The attribute planes as set_planes.
    const V x1 = hn::Sub(v1.x, s0.x), x2 = hn::Sub(v2.x, s0.x);
    const V y1 = hn::Sub(v1.y, s0.y), y2 = hn::Sub(v2.y, s0.y);
    const V inv_area = hn::Div(hn::Set(d, k_subpixel_one), hn::Abs(signed_area));
    const auto [z, q, l1, l2] = set_planes(s0.z, v1.z, v2.z, s0.q, v1.q, v2.q, x1, x2, y1, y2, inv_area);
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
    store_unit(out, 4, i0, word_of_float(hn::Mul(s0.x, scale)), word_of_float(hn::Mul(s0.y, scale)), zq0[0], z.dfdx);
    store_unit(out, 5, i0, z.dfdy, zq0[1], q.dfdx, q.dfdy);
    store_unit(out, 6, i0, l1.dfdx, l1.dfdy, l2.dfdx, l2.dfdy);
    store_unit(out, 7, i0, r0, hn::IfThenElse(flip_u, r2, r1), hn::IfThenElse(flip_u, r1, r2), flags);
    const DI di;
    store_tiles(di, hn::DemoteTo(di, min_x), hn::DemoteTo(di, min_y), hn::DemoteTo(di, max_x), hn::DemoteTo(di, max_y), p,
                out.tile + i0);
    // Groups of large triangles are few: their floors from the records.
    for (std::uint32_t bits = out.floors ? mask_bits(keep) : 0; bits != 0; bits &= bits - 1) {
        const int i = i0 + std::countr_zero(bits);
        TriangleSetup t;
        write_record(out, i, t);
        out.floor[i] = lowest_depth(t);
    }
    return true;
}

#if HWY_TARGET != HWY_SCALAR
// The common case in 32-bit lanes, twice as many per vector: batches of triangles less than 2^14
// (64 pixels) wide and tall, i.e. nearly every batch of a dense mesh. Then every integer of the
// record fits 32 bits, exactly:
//  - the signed area's products of differences below 2^14 are below 2^28;
//  - (cx, cy) = 256 (min_x, min_y) + 128, the centre of the bounds' corner pixel, lies within the
//    vertices' range on each axis when the triangle is kept: cx >= lo_x as min_x >= first_centre(lo_x),
//    and cx <= hi_x as min_x <= max_x <= last_centre(hi_x), scissor or not. So every vertex is
//    within 2^14 of it, and setup_triangle's e0 = floor((C + bias + 128 (A + B)) / 256) + A min_x
//    + B min_y equals floor((bias - A (ax - cx) - B (ay - cy)) / 256) (the integer A min_x + B min_y
//    moves inside the floor as 256 times itself), whose products are below 2^28: the arithmetic
//    shift by 8 of a 32-bit integer is that floor. e0's high word is its sign;
//  - |A|, |B| < 2^14 and |e0| <= 2^21 make every edge small (edges_fit_32_bits).
// The attribute planes stay in double, each half of the lanes in one double vector, with the
// operations of SetUpGroupInDouble. False, having written nothing, when a triangle of the group
// does not qualify: the caller sets the group up in double instead.
constexpr std::int32_t k_extent_limit = 1 << 14;

using DI32 = hn::ScalableTag<std::int32_t>;
using DU32 = hn::RebindToUnsigned<DI32>;
using VI32 = hn::Vec<DI32>;
using MI32 = hn::Mask<DI32>;
static_assert(hn::MaxLanes(hn::Half<DI32>()) == hn::MaxLanes(D()), "half an int32 vector per double vector");

struct Corner32 {
    VI32 x, y, z, q;  // z and q: the float's bits
};

HWY_INLINE Corner32 load_corner32(const ScreenVertex* v) {
    Corner32 c;
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    // As store_unit32, two rounds of two-source permutes (8) where LoadInterleaved4 takes 16
    // shuffles: x and y, z and q of vertices 0-7 and 8-15 paired, then the pairs' halves joined.
    const __m512i take_xy = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 1, 5, 9, 13, 17, 21, 25, 29);
    const __m512i take_zq = _mm512_setr_epi32(2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15, 19, 23, 27, 31);
    const __m512i lower = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23);
    const __m512i upper = _mm512_setr_epi32(8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31);
    const auto* from = reinterpret_cast<const __m512i*>(v);
    const __m512i v0 = _mm512_loadu_si512(from + 0), v1 = _mm512_loadu_si512(from + 1);
    const __m512i v2 = _mm512_loadu_si512(from + 2), v3 = _mm512_loadu_si512(from + 3);
    const __m512i xy_lo = _mm512_permutex2var_epi32(v0, take_xy, v1), zq_lo = _mm512_permutex2var_epi32(v0, take_zq, v1);
    const __m512i xy_hi = _mm512_permutex2var_epi32(v2, take_xy, v3), zq_hi = _mm512_permutex2var_epi32(v2, take_zq, v3);
    c.x = VI32{_mm512_permutex2var_epi32(xy_lo, lower, xy_hi)};
    c.y = VI32{_mm512_permutex2var_epi32(xy_lo, upper, xy_hi)};
    c.z = VI32{_mm512_permutex2var_epi32(zq_lo, lower, zq_hi)};
    c.q = VI32{_mm512_permutex2var_epi32(zq_lo, upper, zq_hi)};
#else
    hn::LoadInterleaved4(DI32(), reinterpret_cast<const std::int32_t*>(v), c.x, c.y, c.z, c.q);
#endif
    return c;
}

HWY_INLINE Corner32 select32(MI32 m, const Corner32& yes, const Corner32& no) {
    return {hn::IfThenElse(m, yes.x, no.x), hn::IfThenElse(m, yes.y, no.y), hn::IfThenElse(m, yes.z, no.z),
            hn::IfThenElse(m, yes.q, no.q)};
}

std::uint32_t mask_bits32(MI32 m) {
    std::uint8_t bits[8] = {};
    hn::StoreMaskBits(DI32(), m, bits);
    return bits[0] | static_cast<std::uint32_t>(bits[1]) << 8;  // at most 16 lanes
}

// Lanes [half * Lanes(D), ...) of an int32 vector, or of the floats whose bits it holds, as doubles.
HWY_INLINE V half_to_double(VI32 v, int half) {
    const hn::Half<DI32> dh;
    return hn::PromoteTo(D(), half == 0 ? hn::LowerHalf(dh, v) : hn::UpperHalf(dh, v));
}
HWY_INLINE V half_float_to_double(VI32 bits, int half) {
    const hn::Half<DI32> dh;
    const hn::Rebind<float, D> dfh;
    return hn::PromoteTo(D(), hn::BitCast(dfh, half == 0 ? hn::LowerHalf(dh, bits) : hn::UpperHalf(dh, bits)));
}
// Two halves' words (each a DU vector) as one vector of words.
HWY_INLINE hn::Vec<DU32> join(VU lower, VU upper) { return hn::Combine(DU32(), upper, lower); }

struct Edge32 {
    VI32 a, b, e0, e0_high;
};

HWY_INLINE Edge32 set_edge32(const Corner32& a, const Corner32& b, VI32 cx, VI32 cy) {
    const DI32 di;
    const VI32 zero = hn::Zero(di);
    const VI32 A = hn::Sub(a.y, b.y), B = hn::Sub(b.x, a.x);
    const MI32 top_left = hn::Or(hn::Gt(A, zero), hn::And(hn::Eq(A, zero), hn::Gt(B, zero)));
    const VI32 bias = hn::IfThenZeroElse(top_left, hn::Set(di, -1));
    const VI32 t = hn::Add(hn::Mul(A, hn::Sub(a.x, cx)), hn::Mul(B, hn::Sub(a.y, cy)));
    const VI32 e0 = hn::ShiftRight<k_subpixel_bits>(hn::Sub(bias, t));
    return {A, B, e0, hn::ShiftRight<31>(e0)};
}

HWY_INLINE void store_unit32(SetupLanes& out, int g, int i0, VI32 w0, VI32 w1, VI32 w2, VI32 w3) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    // Two rounds of two-source permutes (8) where StoreInterleaved4 takes 16 shuffles: words 0-1 and
    // 2-3 of triangles paired, then the pairs joined into each triangle's unit.
    const __m512i pair_lo = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const __m512i pair_hi = _mm512_setr_epi32(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
    const __m512i join_lo = _mm512_setr_epi32(0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23);
    const __m512i join_hi = _mm512_setr_epi32(8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31);
    const __m512i a_lo = _mm512_permutex2var_epi32(w0.raw, pair_lo, w1.raw);
    const __m512i a_hi = _mm512_permutex2var_epi32(w0.raw, pair_hi, w1.raw);
    const __m512i b_lo = _mm512_permutex2var_epi32(w2.raw, pair_lo, w3.raw);
    const __m512i b_hi = _mm512_permutex2var_epi32(w2.raw, pair_hi, w3.raw);
    auto* to = reinterpret_cast<__m512i*>(out.unit[g][i0].word);
    _mm512_storeu_si512(to + 0, _mm512_permutex2var_epi32(a_lo, join_lo, b_lo));
    _mm512_storeu_si512(to + 1, _mm512_permutex2var_epi32(a_lo, join_hi, b_lo));
    _mm512_storeu_si512(to + 2, _mm512_permutex2var_epi32(a_hi, join_lo, b_hi));
    _mm512_storeu_si512(to + 3, _mm512_permutex2var_epi32(a_hi, join_hi, b_hi));
#else
    const DU32 du;
    hn::StoreInterleaved4(hn::BitCast(du, w0), hn::BitCast(du, w1), hn::BitCast(du, w2), hn::BitCast(du, w3), du,
                          out.unit[g][i0].word);
#endif
}

bool SetUpGroupIn32Bits(const SetupBatch& batch, const FrontEndParams& p, SetupLanes& out, int i0) {
    const DI32 di;
    const DU32 du;
    const Corner32 s0 = load_corner32(batch.v[0] + i0), s1 = load_corner32(batch.v[1] + i0),
                   s2 = load_corner32(batch.v[2] + i0);
    const MI32 valid = hn::FirstN(di, batch.count - i0);
    const VI32 lo_x = hn::Min(s0.x, hn::Min(s1.x, s2.x)), hi_x = hn::Max(s0.x, hn::Max(s1.x, s2.x));
    const VI32 lo_y = hn::Min(s0.y, hn::Min(s1.y, s2.y)), hi_y = hn::Max(s0.y, hn::Max(s1.y, s2.y));
    // Inside +-2^24 first (as the double path requires), so that the differences cannot overflow.
    const VI32 coordinate_limit = hn::Set(di, 1 << 24), extent_limit = hn::Set(di, k_extent_limit);
    const MI32 in_range = hn::And(hn::And(hn::Gt(lo_x, hn::Neg(coordinate_limit)), hn::Lt(hi_x, coordinate_limit)),
                                  hn::And(hn::Gt(lo_y, hn::Neg(coordinate_limit)), hn::Lt(hi_y, coordinate_limit)));
    const MI32 narrow = hn::And(hn::Lt(hn::Sub(hi_x, lo_x), extent_limit), hn::Lt(hn::Sub(hi_y, lo_y), extent_limit));
    if (!hn::AllFalse(di, hn::AndNot(hn::And(in_range, narrow), valid))) return false;

    const VI32 signed_area = hn::Sub(hn::Mul(hn::Sub(s1.x, s0.x), hn::Sub(s2.y, s0.y)),
                                     hn::Mul(hn::Sub(s2.x, s0.x), hn::Sub(s1.y, s0.y)));
    const MI32 flip = hn::Lt(signed_area, hn::Zero(di));  // viewer sees it counter-clockwise
    const MI32 front = p.state.front_face == FrontFace::ccw ? flip : hn::Not(flip);
    const MI32 culled = hn::And(culled_lanes(di, signed_area, front, p), valid);

    // first_centre and last_centre of setup.cpp, then the scissor.
    const VI32 half = hn::Set(di, k_subpixel_one / 2);
    const VI32 min_x = hn::Max(hn::Neg(hn::ShiftRight<k_subpixel_bits>(hn::Sub(half, lo_x))), hn::Set(di, p.scissor.x0));
    const VI32 min_y = hn::Max(hn::Neg(hn::ShiftRight<k_subpixel_bits>(hn::Sub(half, lo_y))), hn::Set(di, p.scissor.y0));
    const VI32 max_x = hn::Min(hn::ShiftRight<k_subpixel_bits>(hn::Sub(hi_x, half)), hn::Set(di, p.scissor.x1 - 1));
    const VI32 max_y = hn::Min(hn::ShiftRight<k_subpixel_bits>(hn::Sub(hi_y, half)), hn::Set(di, p.scissor.y1 - 1));
    const MI32 empty = hn::Or(hn::Gt(min_x, max_x), hn::Gt(min_y, max_y));
    const MI32 keep = hn::AndNot(hn::Or(culled, empty), valid);

    out.culled |= mask_bits32(culled) << i0;
    if (hn::AllFalse(di, keep)) return true;

    const Corner32 v1 = select32(flip, s2, s1), v2 = select32(flip, s1, s2);
    const VI32 cx = hn::Add(hn::ShiftLeft<k_subpixel_bits>(min_x), half);
    const VI32 cy = hn::Add(hn::ShiftLeft<k_subpixel_bits>(min_y), half);
    const Edge32 e[3] = {set_edge32(s0, v1, cx, cy), set_edge32(v1, v2, cx, cy), set_edge32(v2, s0, cx, cy)};
    const VI32 e0s[3] = {e[0].e0, e[1].e0, e[2].e0}, as[3] = {e[0].a, e[1].a, e[2].a}, bs[3] = {e[0].b, e[1].b, e[2].b};
    out.keep |= mask_bits32(hn::AndNot(small_and_empty(di, e0s, as, bs, hn::Sub(max_x, min_x), hn::Sub(max_y, min_y)), keep))
                << i0;
    // front_facing, and small_edges always set (see above).
    const VI32 flags = hn::Or(hn::IfThenElseZero(front, hn::Set(di, 1)), hn::Set(di, 1 << 8));
    const VI32 r0 = hn::BitCast(di, hn::LoadU(du, batch.ref[0] + i0));
    const VI32 r1 = hn::BitCast(di, hn::LoadU(du, batch.ref[1] + i0));
    const VI32 r2 = hn::BitCast(di, hn::LoadU(du, batch.ref[2] + i0));
    store_unit32(out, 0, i0, e[0].a, e[1].a, e[2].a, e[0].b);
    store_unit32(out, 1, i0, e[1].b, e[2].b, e[0].e0, e[0].e0_high);
    store_unit32(out, 2, i0, e[1].e0, e[1].e0_high, e[2].e0, e[2].e0_high);
    store_unit32(out, 3, i0, min_x, min_y, max_x, max_y);
    store_unit32(out, 7, i0, r0, hn::IfThenElse(flip, r2, r1), hn::IfThenElse(flip, r1, r2), flags);
    store_tiles(di, min_x, min_y, max_x, max_y, p, out.tile + i0);

    // The attribute planes as SetUpGroupInDouble computes them, half of the lanes at a time.
    const VI32 x1 = hn::Sub(v1.x, s0.x), x2 = hn::Sub(v2.x, s0.x);
    const VI32 y1 = hn::Sub(v1.y, s0.y), y2 = hn::Sub(v2.y, s0.y);
    const VI32 area = hn::Abs(signed_area);
    const D d;
    const V scale = hn::Set(d, 1.0 / k_subpixel_one);
    VU words[2][10];
    for (int h = 0; h < 2; ++h) {
        const V dx1 = half_to_double(x1, h), dx2 = half_to_double(x2, h);
        const V dy1 = half_to_double(y1, h), dy2 = half_to_double(y2, h);
        const V inv_area = hn::Div(hn::Set(d, k_subpixel_one), half_to_double(area, h));
        const V z0 = half_float_to_double(s0.z, h), q0 = half_float_to_double(s0.q, h);
        const V z1 = half_float_to_double(v1.z, h), q1 = half_float_to_double(v1.q, h);
        const V z2 = half_float_to_double(v2.z, h), q2 = half_float_to_double(v2.q, h);
        const auto [z, q, l1, l2] = set_planes(z0, z1, z2, q0, q1, q2, dx1, dx2, dy1, dy2, inv_area);
        VU* w = words[h];
        w[0] = word_of_float(hn::Mul(half_to_double(s0.x, h), scale));
        w[1] = word_of_float(hn::Mul(half_to_double(s0.y, h), scale));
        w[2] = z.dfdx, w[3] = z.dfdy, w[4] = q.dfdx, w[5] = q.dfdy;
        w[6] = l1.dfdx, w[7] = l1.dfdy, w[8] = l2.dfdx, w[9] = l2.dfdy;
    }
    auto joined = [&](int k) { return hn::BitCast(di, join(words[0][k], words[1][k])); };
    store_unit32(out, 4, i0, joined(0), joined(1), s0.z, joined(2));
    store_unit32(out, 5, i0, joined(3), s0.q, joined(4), joined(5));
    store_unit32(out, 6, i0, joined(6), joined(7), joined(8), joined(9));

    if (!out.floors) return true;
    // The floors (lowest_depth): depth_at's operations at the corner the plane falls toward.
    const hn::Rebind<float, DI32> df;
    const auto x0 = hn::BitCast(df, joined(0)), y0 = hn::BitCast(df, joined(1)), z0 = hn::BitCast(df, s0.z);
    const auto gx = hn::BitCast(df, joined(2)), gy = hn::BitCast(df, joined(3));
    const auto zero = hn::Zero(df), steep = hn::Set(df, 1e30f), centre = hn::Set(df, 0.5f);
    const VI32 fx = hn::IfThenElse(hn::RebindMask(di, hn::Lt(gx, zero)), max_x, min_x);
    const VI32 fy = hn::IfThenElse(hn::RebindMask(di, hn::Lt(gy, zero)), max_y, min_y);
    const auto dx = hn::Sub(hn::Add(hn::ConvertTo(df, fx), centre), x0);
    const auto dy = hn::Sub(hn::Add(hn::ConvertTo(df, fy), centre), y0);
    const auto z = hn::Add(hn::Add(z0, hn::Mul(gx, dx)), hn::Mul(gy, dy));
    // Where the three are below 1e30, z is finite: clamped as depth_at clamps it.
    const auto finite = hn::And(hn::And(hn::Lt(hn::Abs(gx), steep), hn::Lt(hn::Abs(gy), steep)), hn::Lt(hn::Abs(z0), steep));
    const auto clamped = hn::Min(hn::Max(z, zero), hn::Set(df, 1.0f));
    hn::StoreU(hn::IfThenElse(finite, clamped, hn::Set(df, -std::numeric_limits<float>::infinity())), df, out.floor + i0);
    return true;
}
#endif

// Returns false, having written nothing useful, when a coordinate is too large for exact doubles.
bool SetupLanesOf(const SetupBatch& batch, const FrontEndParams& p, SetupLanes& out) {
    out.keep = out.culled = 0;  // the caller may reuse `out` batch after batch
    const int lanes = static_cast<int>(hn::Lanes(D()));
#if HWY_TARGET != HWY_SCALAR
    const int lanes32 = static_cast<int>(hn::Lanes(DI32()));
    for (int i0 = 0; i0 < batch.count; i0 += lanes32) {
        if (SetUpGroupIn32Bits(batch, p, out, i0)) continue;
        for (int h = i0; h < i0 + lanes32 && h < batch.count; h += lanes)
            if (!SetUpGroupInDouble(batch, p, out, h)) return false;
    }
#else
    for (int i0 = 0; i0 < batch.count; i0 += lanes)
        if (!SetUpGroupInDouble(batch, p, out, i0)) return false;
#endif
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
