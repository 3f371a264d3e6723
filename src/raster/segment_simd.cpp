// facet raster: a batch of line segments made into their records at once (segment.hpp's
// setup_segment_lanes), compiled per ISA by Highway and dispatched at run time. In: the segments' ends
// and their corners' offsets (or square ends, computed here as square_end does). Out: the records, stored in their byte order four words at a time
// (SetupLanes), and which segments segment_record (segment.cpp, the specification) would leave as two
// triangles. Does not bin.
//
// Why the results are the same bits: the integers (corners, turns, bounds, the edges' A, B and value
// at the origin pixel) are computed in double lanes, where they are exact: ends below 2^23 in
// magnitude and offsets below 2^22 (the guard band keeps ends below 2^22; the widest line's mitred
// offsets are below 2^18) keep corners below 2^24, their differences below 2^25, every product below
// 2^50 and every sum below 2^52; floor(c / 256) is the arithmetic right shift. A batch outside that
// range goes one by one. A parallelogram's four turns are one number, so testing all four (the
// kernel) or the first (segment_record, for square ends) decides alike. The planes are the same
// double operations in the same order (no FMA: -ffp-contract=off, and Highway's Mul, Sub and Div
// round separately), converted to float to nearest as static_cast does.
#include <cstdint>

#include "raster/segment.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/segment_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "setup/record_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// An end of the group's segments, its coordinates widened to double (exactly), z and q also as stored.
struct End {
    V x, y, z, q;
    VU z_bits, q_bits;
};

HWY_INLINE End load_end(const ScreenVertex* v) {
    const DI di;
    hn::Vec<DI> x, y, z, q;
    hn::LoadInterleaved4(di, reinterpret_cast<const std::int32_t*>(v), x, y, z, q);
    const D d;
    const DF df;
    return {hn::PromoteTo(d, x),
            hn::PromoteTo(d, y),
            hn::PromoteTo(d, hn::BitCast(df, z)),
            hn::PromoteTo(d, hn::BitCast(df, q)),
            hn::BitCast(DU(), z),
            hn::BitCast(DU(), q)};
}

HWY_INLINE V load_offset(const std::int32_t* p) { return hn::PromoteTo(D(), hn::LoadU(DI(), p)); }

// Segments i0 .. i0 + Lanes(D) - 1 of the batch. False, having written nothing useful, when a
// coordinate is outside the exact range.
bool SetUpSegmentGroup(const SegmentBatch& batch, const PixelRect& scissor, SetupLanes& out, int i0) {
    const D d;
    const DU du;
    const End a = load_end(batch.a + i0), b = load_end(batch.b + i0);
    const V dx = hn::Sub(b.x, a.x), dy = hn::Sub(b.y, a.y);
    // Square ends where asked, as square_end: round_half_away(-dy / length * h * 256) and
    // round_half_away(dx / length * h * 256), the rounding from an exact truncation.
    const M square = hn::Ne(load_offset(batch.square + i0), hn::Zero(d));
    const V length = hn::Sqrt(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)));
    const V h = hn::Set(d, batch.half_width), one = hn::Set(d, 1.0), half_one = hn::Set(d, 0.5);
    const auto round_half_away = [&](V v) {
        const V i = hn::Trunc(v), f = hn::Sub(v, i);
        return hn::Sub(hn::Add(i, hn::IfThenElseZero(hn::Ge(f, half_one), one)),
                       hn::IfThenElseZero(hn::Le(f, hn::Neg(half_one)), one));
    };
    const V scale_256 = hn::Set(d, k_subpixel_one);
    const V square_x = round_half_away(hn::Mul(hn::Mul(hn::Div(hn::Neg(dy), length), h), scale_256));
    const V square_y = round_half_away(hn::Mul(hn::Mul(hn::Div(dx, length), h), scale_256));
    const M valid = hn::FirstN(d, static_cast<std::size_t>(batch.count - i0));
    // Every segment with square ends (a line list's): parallelograms, whose offsets are the square
    // ones and whose four turns are one number (the first decides, as in segment_record).
    const bool parallelograms = hn::AllTrue(d, hn::Or(square, hn::Not(valid)));
    V ox0 = square_x, oy0 = square_y, ox1 = square_x, oy1 = square_y;
    if (!parallelograms) {
        ox0 = hn::IfThenElse(square, square_x, load_offset(batch.ox0 + i0));
        oy0 = hn::IfThenElse(square, square_y, load_offset(batch.oy0 + i0));
        ox1 = hn::IfThenElse(square, square_x, load_offset(batch.ox1 + i0));
        oy1 = hn::IfThenElse(square, square_y, load_offset(batch.oy1 + i0));
    }
    const V ends = hn::Max(hn::Max(hn::Abs(a.x), hn::Abs(a.y)), hn::Max(hn::Abs(b.x), hn::Abs(b.y)));
    const V offsets = hn::Max(hn::Max(hn::Abs(ox0), hn::Abs(oy0)), hn::Max(hn::Abs(ox1), hn::Abs(oy1)));
    if (!hn::AllTrue(d, hn::And(hn::Lt(ends, hn::Set(d, 8388608.0)), hn::Lt(offsets, hn::Set(d, 4194304.0)))))
        return false;

    const V cx[4] = {hn::Add(a.x, ox0), hn::Sub(a.x, ox0), hn::Sub(b.x, ox1), hn::Add(b.x, ox1)};
    const V cy[4] = {hn::Add(a.y, oy0), hn::Sub(a.y, oy0), hn::Sub(b.y, oy1), hn::Add(b.y, oy1)};
    const V zero = hn::Zero(d);
    M positive = valid, negative = valid;
    for (int k = 0; k < (parallelograms ? 1 : 4); ++k) {
        const int q = (k + 1) % 4, r = (k + 2) % 4;
        const V turn = hn::Sub(hn::Mul(hn::Sub(cx[q], cx[k]), hn::Sub(cy[r], cy[q])),
                               hn::Mul(hn::Sub(cy[q], cy[k]), hn::Sub(cx[r], cx[q])));
        positive = hn::And(positive, hn::Gt(turn, zero));
        negative = hn::And(negative, hn::Lt(turn, zero));
    }
    const M convex = hn::Or(positive, negative);
    // Counter-clockwise, as segment_record orients the quad.
    const V vx[4] = {cx[0], hn::IfThenElse(positive, cx[1], cx[3]), cx[2], hn::IfThenElse(positive, cx[3], cx[1])};
    const V vy[4] = {cy[0], hn::IfThenElse(positive, cy[1], cy[3]), cy[2], hn::IfThenElse(positive, cy[3], cy[1])};
    const V half = hn::Set(d, k_subpixel_one / 2);
    const V lo_x = hn::Min(hn::Min(vx[0], vx[1]), hn::Min(vx[2], vx[3]));
    const V hi_x = hn::Max(hn::Max(vx[0], vx[1]), hn::Max(vx[2], vx[3]));
    const V lo_y = hn::Min(hn::Min(vy[0], vy[1]), hn::Min(vy[2], vy[3]));
    const V hi_y = hn::Max(hn::Max(vy[0], vy[1]), hn::Max(vy[2], vy[3]));
    const V min_x = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_x))), hn::Set(d, scissor.x0));
    const V max_x = hn::Min(floor_div_256(hn::Sub(hi_x, half)), hn::Set(d, scissor.x1 - 1));
    const V min_y = hn::Max(hn::Neg(floor_div_256(hn::Sub(half, lo_y))), hn::Set(d, scissor.y0));
    const V max_y = hn::Min(floor_div_256(hn::Sub(hi_y, half)), hn::Set(d, scissor.y1 - 1));
    const M empty = hn::Or(hn::Gt(min_x, max_x), hn::Gt(min_y, max_y));

    // The edges relative to a's pixel: A, B and c = floor((A (256 ox + 128 - x) + B (256 oy + 128 - y)
    // + bias) / 256), as pixel_edge.
    const V ox = floor_div_256(a.x), oy = floor_div_256(a.y);
    const V reach = hn::Max(hn::Max(hn::Sub(ox, min_x), hn::Sub(max_x, ox)), hn::Max(hn::Sub(oy, min_y), hn::Sub(max_y, oy)));
    const V centre_x = hn::Add(hn::Mul(ox, hn::Set(d, k_subpixel_one)), half);
    const V centre_y = hn::Add(hn::Mul(oy, hn::Set(d, k_subpixel_one)), half);
    const V int32_max = hn::Set(d, 2147483647.0), int32_min = hn::Set(d, -2147483648.0);
    M fits = valid, small = valid;
    VU ea[4], eb[4], ee[4];
    for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        const V A = hn::Sub(vy[k], vy[n]), B = hn::Sub(vx[n], vx[k]);
        const M top_left = hn::Or(hn::Gt(A, zero), hn::And(hn::Eq(A, zero), hn::Gt(B, zero)));
        const V bias = hn::IfThenZeroElse(top_left, hn::Set(d, -1.0));
        const V c = hn::Add(hn::Add(hn::Mul(A, hn::Sub(centre_x, vx[k])), hn::Mul(B, hn::Sub(centre_y, vy[k]))), bias);
        const V at = floor_div_256(c);
        fits = hn::And(fits, hn::And(hn::Ge(at, int32_min), hn::Le(at, int32_max)));
        small = hn::And(small, hn::Le(hn::Add(hn::Abs(at), hn::Mul(hn::Add(hn::Abs(A), hn::Abs(B)), reach)), int32_max));
        // Out-of-range lanes are not kept: clamped, so that the conversion is defined.
        ea[k] = word_of_integer(A), eb[k] = word_of_integer(B);
        ee[k] = word_of_integer(hn::Min(hn::Max(at, int32_min), int32_max));
    }
    const M drawn = hn::AndNot(empty, convex);
    const M keep = hn::And(drawn, fits);
    out.keep |= mask_bits(keep) << i0;
    out.culled |= mask_bits(hn::And(valid, hn::Or(hn::Not(convex), hn::AndNot(fits, drawn)))) << i0;
    if (hn::AllFalse(d, keep)) return true;

    // The planes, as segment_record.
    const V per_length2 = hn::Div(hn::Set(d, k_subpixel_one), hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)));
    const V sx = hn::Mul(dx, per_length2), sy = hn::Mul(dy, per_length2);
    const V dz = hn::Sub(b.z, a.z), dq = hn::Sub(b.q, a.q);
    const V scale = hn::Set(d, 1.0 / k_subpixel_one);
    // dl2dx = dl2dy = +0 in every kept lane (per_length2 is finite and positive there), computed
    // rather than constant: with constant zero words the compiler interleaves them with a register
    // vmovq that valgrind (3.19, the project's instruction counter) cannot run.
    const VU zero_word = word_of_float(hn::Mul(hn::Zero(d), per_length2));
    const VU ref_a = hn::LoadU(du, batch.ref_a + i0), ref_b = hn::LoadU(du, batch.ref_b + i0);
    // front_facing, small_edges and segment, a byte each.
    const VU flags = hn::Or(hn::Set(du, 1u | (1u << 16)), hn::IfThenElseZero(word_mask(small), hn::Set(du, 1u << 8)));
    store_unit(out, 0, i0, ea[0], ea[1], ea[2], ea[3]);
    store_unit(out, 1, i0, eb[0], eb[1], eb[2], eb[3]);
    store_unit(out, 2, i0, ee[0], ee[1], ee[2], ee[3]);
    store_unit(out, 3, i0, word_of_integer(min_x), word_of_integer(min_y), word_of_integer(max_x), word_of_integer(max_y));
    store_unit(out, 4, i0, word_of_float(hn::Mul(a.x, scale)), word_of_float(hn::Mul(a.y, scale)), a.z_bits,
               word_of_float(hn::Mul(dz, sx)));
    store_unit(out, 5, i0, word_of_float(hn::Mul(dz, sy)), a.q_bits, word_of_float(hn::Mul(dq, sx)),
               word_of_float(hn::Mul(dq, sy)));
    store_unit(out, 6, i0, word_of_float(hn::Mul(b.q, sx)), word_of_float(hn::Mul(b.q, sy)), zero_word, zero_word);
    store_unit(out, 7, i0, ref_a, ref_b, ref_b, flags);
    return true;
}

bool SetUpSegmentLanes(const SegmentBatch& batch, const PixelRect& scissor, SetupLanes& out) {
    out.keep = out.culled = 0;
    const int lanes = static_cast<int>(hn::Lanes(D()));
    for (int i0 = 0; i0 < batch.count; i0 += lanes)
        if (!SetUpSegmentGroup(batch, scissor, out, i0)) return false;
    return true;
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(SetUpSegmentLanes);

bool setup_segment_lanes(const SegmentBatch& batch, const PixelRect& scissor, SetupLanes& lanes) {
    return !use_scalar_kernels() && HWY_DYNAMIC_DISPATCH(SetUpSegmentLanes)(batch, scissor, lanes);
}

}  // namespace facet::detail
#endif
