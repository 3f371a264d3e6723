// facet tile pass: the depth pass, pass one of the visible-only order (depth_pass.hpp), as a SIMD kernel,
// compiled per ISA by Highway and dispatched at run time. Coverage and depth are computed in one
// sweep: the triangle's bounds within the tile are cut into column strips one vector wide, and each
// row of a strip evaluates the three edge functions (exact 32-bit integers, as in coverage_simd.cpp),
// the depth, the depth test and the owner write in lanes, with no coverage bitmask in between. For
// the small triangles of scanned meshes a strip is one vector per row, and the per-tile coverage pass
// with its separate setup disappears. Lanes compute each pixel's depth with the same operations in
// the same order as depth_at (no FMA: the project builds with -ffp-contract=off and Highway's Mul
// and Add round separately), so every ISA writes the bytes of the scalar specification,
// resolve_triangle_reference in depth_pass.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tile/depth_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <utility>

#include "raster/segment.hpp"
#include "tile/depth_pass.hpp"
#include "simd/masked_compare-inl.h"

#ifndef FACET_TILE_DEPTH_SIMD_ONCE
#define FACET_TILE_DEPTH_SIMD_ONCE
namespace facet::detail {

// The triangle's (K = 3) or segment's (K = 4) pixel bounds within a tile (inclusive) and its edges in
// the 32-bit form the lanes evaluate, as coverage.cpp's rasterize_tile prepares them: an edge that is
// >= 0 over the whole rectangle becomes e = a = b = 0 (its values there may not fit in 32 bits; it
// decides nothing), and the others vary by less than 2^31 over the rectangle, so they fit.
template <int K>
struct EdgeRectOf {
    static constexpr int k_edges = K;
    int x0, y0, x1, y1;
    int ex;                          // the column e is given at: x0, or (32-bit edges) the record's first
    std::uint32_t e[K], a[K], b[K];  // value at (ex, y0), step per column, per row; unsigned: lanes wrap
};
using EdgeRect = EdgeRectOf<3>;

// r's x0, y0, x1, y1: t's pixel bounds within the tile. False when they miss it.
template <class R>
HWY_INLINE bool bounds_in_tile(const TriangleSetup& t, PixelRect tile, R& r) {
    r.x0 = std::max(tile.x0, t.min_x), r.y0 = std::max(tile.y0, t.min_y);
    r.x1 = std::min(tile.x1 - 1, t.max_x), r.y1 = std::min(tile.y1 - 1, t.max_y);
    return !((r.x0 > r.x1) | (r.y0 > r.y1));  // one branch, not two
}

// Edge k of r from its value at (r.x0, r.y0) and its steps, exact in 64 bits (r.ex is r.x0). False
// when it is negative over the whole rectangle.
template <int K>
HWY_INLINE bool set_crossing_edge(EdgeRectOf<K>& r, int k, std::int64_t first, std::int32_t a, std::int32_t b) {
    const std::int64_t w1 = r.x1 - r.x0, h1 = r.y1 - r.y0;
    const std::int64_t min = first + std::min<std::int64_t>(a, 0) * w1 + std::min<std::int64_t>(b, 0) * h1;
    const std::int64_t max = first + std::max<std::int64_t>(a, 0) * w1 + std::max<std::int64_t>(b, 0) * h1;
    if (max < 0) return false;
    const bool crosses = min < 0;
    r.e[k] = crosses ? static_cast<std::uint32_t>(first) : 0;
    r.a[k] = crosses ? static_cast<std::uint32_t>(a) : 0;
    r.b[k] = crosses ? static_cast<std::uint32_t>(b) : 0;
    return true;
}

// False when the bounds miss the tile or some edge is negative over the whole rectangle.
HWY_INLINE bool edge_rect(const TriangleSetup& t, PixelRect tile, EdgeRect& r) {
    r.x0 = std::max(tile.x0, t.min_x), r.y0 = std::max(tile.y0, t.min_y);
    r.x1 = std::min(tile.x1 - 1, t.max_x), r.y1 = std::min(tile.y1 - 1, t.max_y);
    if (r.x0 > r.x1 || r.y0 > r.y1) return false;  // not bounds_in_tile: two branches measured cheaper here
    if (t.small_edges) {
        // Every value fits, so 32-bit arithmetic that wraps gives each edge at the rectangle's corner
        // exactly. An edge >= 0 everywhere decides nothing, and one < 0 everywhere leaves no pixel
        // inside: the result is the general case's.
        // e is given at the record's first column (the strips step it from there).
        const auto dy = static_cast<std::uint32_t>(r.y0 - t.min_y);
        r.ex = t.min_x;
        for (int k = 0; k < 3; ++k) {
            r.a[k] = static_cast<std::uint32_t>(t.a[k]);
            r.b[k] = static_cast<std::uint32_t>(t.b[k]);
            r.e[k] = static_cast<std::uint32_t>(t.e0[k]) + r.b[k] * dy;
        }
        return true;
    }
    r.ex = r.x0;
    for (int k = 0; k < 3; ++k)
        if (!set_crossing_edge(r, k, edge_at(t, k, r.x0, r.y0), t.a[k], t.b[k])) return false;
    return true;
}

// edge_rect for a segment's record (raster/segment.hpp) whose values do not all fit in 32 bits: its
// four edges as the triangle's three.
HWY_INLINE bool segment_edge_rect(const TriangleSetup& t, PixelRect tile, EdgeRectOf<4>& r) {
    if (!bounds_in_tile(t, tile, r)) return false;
    const SegmentEdges s = segment_edges(t);
    const PixelIndex origin = segment_origin(t);
    r.ex = r.x0;
    for (int k = 0; k < 4; ++k)
        if (!set_crossing_edge(r, k, segment_edge_at(s, origin, k, r.x0, r.y0), s.a[k], s.b[k])) return false;
    return true;
}

// The rectangle of a segment whose edges all fit in 32 bits over its bounds (small_edges, nearly
// all): the strips read the four edges from the record itself, where each strip starts
// (edge_vectors), in one 4-lane step rather than one edge at a time through copies.
struct SmallSegmentRect {
    static constexpr int k_edges = 4;
    int x0, y0, x1, y1;
    const TriangleSetup* t;
    PixelIndex origin;  // segment_origin(*t)
};

}  // namespace facet::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Where the covered lanes pass the depth test (on AVX-512 one compare under the covered mask).
template <DepthTest D, class DF, class M>
M depth_test(DF df, hn::Vec<DF> z, hn::Vec<DF> stored, M covered) {
    if constexpr (D == DepthTest::less) return and_compare<Compare::lt>(df, covered, z, stored);
    else if constexpr (D == DepthTest::lequal) return and_compare<Compare::le>(df, covered, z, stored);
    else if constexpr (D == DepthTest::equal) return and_compare<Compare::eq>(df, covered, z, stored);
    else if constexpr (D == DepthTest::greater) return and_compare<Compare::gt>(df, covered, z, stored);
    else {
        static_assert(D == DepthTest::always, "never draws nothing (DrawOrder::nothing): no kernel");
        return covered;
    }
}

// depth_at's clamp, z < 0 ? 0 : (z > 1 ? 1 : z), bit for bit. On x86 Max(0, z) and Min(1, z) are
// one instruction each that returns its second operand when either is NaN or both are equal, so
// NaN and -0 pass through unchanged exactly as in the comparisons (two operations instead of four,
// 2-3% of a mesh's tile pass). Highway's portable Max and Min do not promise that: other targets compare.
template <class DF>
HWY_INLINE hn::Vec<DF> clamp_depth(DF df, hn::Vec<DF> z) {
    const auto zero = hn::Zero(df), one = hn::Set(df, 1.0f);
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    return hn::Min(one, hn::Max(zero, z));
#else
    return hn::IfThenElse(hn::Lt(z, zero), zero, hn::IfThenElse(hn::Gt(z, one), one, z));
#endif
}

// The OR of K edge vectors: covered where every edge function is >= 0, i.e. no sign bit in it.
template <int K, class V>
HWY_INLINE V or_of(const V (&e)[K]) {
    V v = e[0];
    for (int k = 1; k < K; ++k) v = hn::Or(v, e[k]);
    return v;
}

// The lanes of `in_rect` inside the triangle: where no edge is negative (no sign bit in or_of(e)). On
// AVX-512 one compare under the mask.
template <int K, class DI, class M>
HWY_INLINE M inside_of(DI di, const hn::Vec<DI> (&e)[K], M in_rect) {
    const auto v = or_of(e);
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    return and_compare<Compare::ge>(di, in_rect, v, hn::Zero(di));
#else
    return hn::AndNot(hn::Lt(v, hn::Zero(di)), in_rect);
#endif
}

// Each edge of a rectangle along a strip's first row, r.y0: e[k] lane j is edge k at column
// start + column[j], b[k] its step per row in every lane. What a strip's rows start from.
template <class DI, int K>
HWY_INLINE void edge_vectors(DI di, const EdgeRectOf<K>& r, int start, hn::Vec<DI> column, hn::Vec<DI> (&e)[K],
                             hn::Vec<DI> (&b)[K]) {
    for (int k = 0; k < K; ++k) {
        const std::uint32_t at_start = r.e[k] + r.a[k] * static_cast<std::uint32_t>(start - r.ex);
        e[k] = hn::Add(hn::Set(di, static_cast<std::int32_t>(at_start)),
                       hn::Mul(hn::Set(di, static_cast<std::int32_t>(r.a[k])), column));
        b[k] = hn::Set(di, static_cast<std::int32_t>(r.b[k]));
    }
}

// A small segment's four edges at (start, r.y0) in one step: its record's a[4], b[4] and e[4]
// (SegmentEdges, 16 bytes each) loaded into every 128-bit block, e + a (start - origin.x) +
// b (r.y0 - origin.y) in unsigned lanes that wrap (exact where the value fits: over the bounds, by
// small_edges; lanes outside them are never inside), then lane k spread to edge k's vector.
template <int k, class DI, class V>
HWY_INLINE hn::Vec<DI> spread_lane(DI di, V v) {
    return hn::BitCast(di, hn::Broadcast<k>(v));
}
template <class DI>
HWY_INLINE void edge_vectors(DI di, const SmallSegmentRect& r, int start, hn::Vec<DI> column, hn::Vec<DI> (&e)[4],
                             hn::Vec<DI> (&b)[4]) {
    static_assert(sizeof(SegmentEdges) == 48 && offsetof(SegmentEdges, b) == 16 && offsetof(SegmentEdges, e) == 32,
                  "a[4], b[4], e[4]: one 128-bit block each");
#if HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    if constexpr (hn::MaxLanes(di) >= 4) {
        const hn::RebindToUnsigned<DI> du;
        const auto* record = reinterpret_cast<const std::uint32_t*>(r.t);
        const auto a = hn::LoadDup128(du, record), b4 = hn::LoadDup128(du, record + 4);
        const auto at_start = hn::Add(hn::LoadDup128(du, record + 8),
                                      hn::Add(hn::Mul(a, hn::Set(du, static_cast<std::uint32_t>(start - r.origin.x))),
                                              hn::Mul(b4, hn::Set(du, static_cast<std::uint32_t>(r.y0 - r.origin.y)))));
        [&]<int... k>(std::integer_sequence<int, k...>) {
            ((e[k] = hn::Add(spread_lane<k>(di, at_start), hn::Mul(spread_lane<k>(di, a), column)),
              b[k] = spread_lane<k>(di, b4)),
             ...);
        }(std::make_integer_sequence<int, 4>{});
        return;
    }
#endif
    const SegmentEdges s = segment_edges(*r.t);  // one lane (the scalar target): edge by edge
    const auto dx = static_cast<std::uint32_t>(start - r.origin.x), dy = static_cast<std::uint32_t>(r.y0 - r.origin.y);
    for (int k = 0; k < 4; ++k) {
        const auto a = static_cast<std::uint32_t>(s.a[k]), b_k = static_cast<std::uint32_t>(s.b[k]);
        const auto at_start = static_cast<std::int32_t>(static_cast<std::uint32_t>(s.e[k]) + a * dx + b_k * dy);
        e[k] = hn::Add(hn::Set(di, at_start), hn::Mul(hn::Set(di, s.a[k]), column));
        b[k] = hn::Set(di, s.b[k]);
    }
}

// A row's vector of the tile's depth or owner array: aligned (a strip starts at a multiple of the
// lane count) or not (a narrow segment's vector starts at its first column).
template <bool Aligned, class DV>
HWY_INLINE hn::Vec<DV> load_row(DV d, const hn::TFromD<DV>* p) {
    if constexpr (Aligned) return hn::Load(d, p);
    else return hn::LoadU(d, p);
}
template <bool Aligned, class DV>
HWY_INLINE void store_row(hn::Vec<DV> v, DV d, hn::TFromD<DV>* p) {
    if constexpr (Aligned) hn::Store(v, d, p);
    else hn::StoreU(v, d, p);
}

// Rows are drawn in groups of this many, unrolled, the group's rows past the rectangle computed
// with no pixel inside: most triangles of dense meshes are one or two rows tall within a tile, and a
// row loop whose trip count changes from one triangle to the next mispredicts its exit about once
// per triangle (measured: groups of 2 and 4 equal on the scanned meshes, 2 5% faster on the 1M sphere).
constexpr int k_row_group = 2;

// Narrows [first, last] (rows counted from a strip's first, within 0..63) to the rows where v + b row >=
// 0: an edge's largest value over the strip's columns, v on the first row, changing by b per row. With
// no branch on the signs (they are as good as random). Exact: v and b are below 2^31 in magnitude, so
// double holds them, and -v / b is within 2^-22 / |b| of the quotient, which is at least 1 / |b| from
// any integer it is not: the floor and ceiling are the quotient's.
HWY_INLINE void rows_not_negative(std::int32_t v, std::int32_t b, int& first, int& last) {
    const double q = -static_cast<double>(v) / static_cast<double>(b != 0 ? b : 1);
    const int from = static_cast<int>(std::clamp(std::ceil(q), 0.0, 64.0));    // b > 0: rows from here on
    const int to = static_cast<int>(std::clamp(std::floor(q), -1.0, 64.0));    // b < 0: rows up to here
    first = b > 0 ? std::max(first, from) : first;
    last = b < 0 ? std::min(last, to) : (b == 0 && v < 0 ? -1 : last);
}

// A strip's rows that may have a pixel inside, [first, last] counted from r.y0: those where no edge is
// negative at every one of the strip's columns start + lo .. start + hi (then nothing is inside). Each
// edge's largest value over them on a row is at an end (the edges are linear). False when there are
// none.
template <int K>
HWY_INLINE bool rows_with_pixels(const EdgeRectOf<K>& r, int start, int lo, int hi, int& first, int& last) {
    first = 0, last = r.y1 - r.y0;
    for (int k = 0; k < K; ++k) {
        // Exact: (start + lo, r.y0) and (start + hi, r.y0) are in the rectangle, where the edge fits
        // 32 bits, and r.ex <= start + lo.
        const std::uint32_t at_lo = r.e[k] + r.a[k] * static_cast<std::uint32_t>(start + lo - r.ex);
        const std::uint32_t at_hi = at_lo + r.a[k] * static_cast<std::uint32_t>(hi - lo);
        const auto largest = static_cast<std::int32_t>(static_cast<std::int32_t>(r.a[k]) < 0 ? at_lo : at_hi);
        rows_not_negative(largest, static_cast<std::int32_t>(r.b[k]), first, last);
    }
    return first <= last;
}

// In the kernels for large triangles (resolve_bin_kernel's `large`), the rectangles at least this wide
// and tall draw only rows_with_pixels of each strip. Smaller ones have too few rows to skip to pay for
// the set-up (docs/BENCHMARKS.md, session 14).
constexpr int k_large_columns = 17, k_large_rows = 16;

// One strip of the rectangle: columns [start, start + lanes) of the tile, of which lanes lo..hi
// (relative to start) are the rectangle's, every row y0..y1. With Aligned, start - tile.x0 is a
// multiple of the lane count, so the strip's rows of the tile's depth and owner arrays are aligned
// vectors; without, start + lanes <= tile.x0 + k_max_tile_size (inside the arrays' rows). A row past
// the rectangle (in the last group) is loaded and stored unchanged, past the tile in the arrays'
// spare row (TileBuffers::k_rows). With Trimmed (a large triangle's strip, aligned), only the rows
// from the first to the last that have pixels (rows_with_pixels; the others would pass nowhere), each
// drawn as the others are: the same bytes.
template <DepthTest D, bool DepthWrite, bool Aligned = true, bool Trimmed = false, class DF, class R>
HWY_INLINE bool resolve_strip(DF df, const TriangleSetup& t, PixelRect tile, TileBuffers& buffers,
                              std::uint32_t id, const R& r, int start, int lo, int hi) {
    constexpr int K = R::k_edges;
    static_assert(!Trimmed || Aligned);
    int y0 = r.y0, y1 = r.y1;  // the rows drawn
    if constexpr (Trimmed) {
        int first, last;
        if (!rows_with_pixels(r, start, lo, hi, first, last)) return false;
        y0 = r.y0 + first, y1 = r.y0 + last;
    }
    const hn::RebindToSigned<DF> di;
    const hn::RebindToUnsigned<DF> du;
    using VI = hn::Vec<decltype(di)>;
    const VI iota = hn::Iota(di, 0);
    const auto columns = hn::And(hn::Gt(iota, hn::Set(di, lo - 1)), hn::Lt(iota, hn::Set(di, hi + 1)));
    VI e[K], b[K];
    edge_vectors(di, r, start, iota, e, b);
    if constexpr (Trimmed)
        for (int k = 0; k < K; ++k) e[k] = hn::Add(e[k], hn::Mul(b[k], hn::Set(di, y0 - r.y0)));
    // z = (z0 + dzdx dx) + dzdy dy as depth_at; the first sum is the same for every row.
    const auto dx = hn::Sub(hn::Add(hn::Iota(df, static_cast<float>(start)), hn::Set(df, 0.5f)), hn::Set(df, t.x0));
    const auto z_x = hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.dzdx), dx));
    const auto owner_id = hn::Set(du, id);
    static_assert(k_row_group - 1 <= TileBuffers::k_rows - k_max_tile_size, "a group's rows past the tile are in the arrays");
    float* depth = buffers.depth + (y0 - tile.y0) * k_max_tile_size + (start - tile.x0);
    std::uint32_t* owner = buffers.owner + (y0 - tile.y0) * k_max_tile_size + (start - tile.x0);
    auto passed = hn::FirstN(df, 0);
    // Row y's centre, float(y) + 0.5, counted rather than converted per row: the same bits (exact
    // below 2^23).
    float centre = static_cast<float>(y0) + 0.5f;
    for (int y = y0; y <= y1; y += k_row_group) {
        const VI rows_left = hn::Set(di, y1 - y + 1);
        HWY_UNROLL(2)  // k_row_group: straight-line code
        for (int g = 0; g < k_row_group; ++g) {
            // Covered where every edge function is >= 0: no sign bit in their OR.
            // The group's first row is always in the rectangle (the loop's condition).
            const auto in_rect = g == 0 ? columns : and_less(di, columns, hn::Set(di, g), rows_left);
            const auto inside = inside_of(di, e, in_rect);
            for (int k = 0; k < K; ++k) e[k] = hn::Add(e[k], b[k]);
            const float dy = centre - t.y0;
            centre += 1.0f;
            auto z = hn::Add(z_x, hn::Set(df, t.dzdy * dy));
            z = clamp_depth(df, z);
            const auto stored = load_row<Aligned>(df, depth);
            const auto pass = depth_test<D>(df, z, stored, hn::RebindMask(df, inside));
            if constexpr (DepthWrite) store_row<Aligned>(hn::IfThenElse(pass, z, stored), df, depth);
            if constexpr (Trimmed) hn::BlendedStore(owner_id, hn::RebindMask(du, pass), du, owner);
            else store_row<Aligned>(hn::IfThenElse(hn::RebindMask(du, pass), owner_id, load_row<Aligned>(du, owner)), du, owner);
            passed = hn::Or(passed, pass);
            depth += k_max_tile_size, owner += k_max_tile_size;
        }
    }
    return !hn::AllFalse(df, passed);
}

#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
// A rectangle within 8 aligned columns and at least 3 rows, two rows per 16-lane vector: lanes 0-7
// are columns start..start+7 of row y, lanes 8-15 the same columns of row y + 1. Where a 512-bit
// operation costs what a 256-bit one does (AMD's Zen 5, Intel's cores; Zen 4 runs it as two halves)
// this halves the rows' arithmetic; each lane computes its pixel exactly as resolve_strip does (the
// same edge integers, the same float operations for the depth), so the bytes are the same. Rows are
// drawn in unrolled groups of two vectors (four rows); a group's rows past the rectangle are loaded
// and stored back unchanged, past the tile in the arrays' spare rows. Measured on Zen 5 (A/B runs of
// facet render --benchmark, 1 thread, 1920x1080): the armadillo 2.8% faster; for rectangles of one
// or two rows, most of the 1M sphere's, the wider set-up cost more than it saved (sphere 2.5%
// slower), so those keep resolve_strip's single group of two 8-lane rows.
constexpr int k_pair_group = 2;  // vectors per group
template <DepthTest D, bool DepthWrite, bool Aligned = true, class R>
HWY_INLINE bool resolve_row_pairs(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id,
                                  const R& r, int start, int lo, int hi) {
    constexpr int K = R::k_edges;
    const hn::Full512<float> df;
    const hn::Full256<float> dh;
    const hn::RebindToSigned<decltype(df)> di;
    const hn::RebindToUnsigned<decltype(dh)> duh;
    using VI = hn::Vec<decltype(di)>;
    const VI iota = hn::Iota(di, 0);
    const VI column = hn::And(iota, hn::Set(di, 7)), row = hn::ShiftRight<3>(iota);
    const auto columns = hn::And(hn::Gt(column, hn::Set(di, lo - 1)), hn::Lt(column, hn::Set(di, hi + 1)));
    VI e[K], b2[K];
    edge_vectors(di, r, start, column, e, b2);
    for (int k = 0; k < K; ++k) {  // lanes 8-15 a row below lanes 0-7; two rows per step
        e[k] = hn::Add(e[k], hn::Mul(b2[k], row));
        b2[k] = hn::Add(b2[k], b2[k]);
    }
    const auto dx = hn::Sub(hn::Add(hn::ConvertTo(df, hn::Add(column, hn::Set(di, start))), hn::Set(df, 0.5f)),
                            hn::Set(df, t.x0));
    const auto z_x = hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.dzdx), dx));
    const auto dzdy = hn::Set(df, t.dzdy), y0 = hn::Set(df, t.y0), half = hn::Set(df, 0.5f);
    const auto owner_id = hn::Set(duh, id);
    static_assert(2 * k_pair_group - 1 <= TileBuffers::k_rows - k_max_tile_size,
                  "a group's rows past the tile are in the arrays");
    float* depth = buffers.depth + (r.y0 - tile.y0) * k_max_tile_size + (start - tile.x0);
    std::uint32_t* owner = buffers.owner + (r.y0 - tile.y0) * k_max_tile_size + (start - tile.x0);
    __mmask16 passed = 0;
    // Each lane's row centre, float(y + row) + 0.5, counted as in resolve_strip.
    auto centres = hn::Add(hn::ConvertTo(df, hn::Add(row, hn::Set(di, r.y0))), half);
    const auto two = hn::Set(df, 2.0f);
    for (int y = r.y0; y <= r.y1; y += 2 * k_pair_group) {
        const VI rows_left = hn::Set(di, r.y1 - y + 1);
        HWY_UNROLL(2)  // k_pair_group: straight-line code
        for (int g = 0; g < k_pair_group; ++g) {
            const VI row_g = hn::Add(row, hn::Set(di, 2 * g));
            const auto in_rect = and_less(di, columns, row_g, rows_left);
            const auto inside = inside_of(di, e, in_rect);
            for (int k = 0; k < K; ++k) e[k] = hn::Add(e[k], b2[k]);
            // (y + row + 0.5) - y0 per lane: the float operations of resolve_strip's dy.
            const auto dy = hn::Sub(centres, y0);
            centres = hn::Add(centres, two);
            auto z = hn::Add(z_x, hn::Mul(dzdy, dy));
            z = clamp_depth(df, z);
            const auto stored =
                hn::Combine(df, load_row<Aligned>(dh, depth + k_max_tile_size), load_row<Aligned>(dh, depth));
            const auto pass = depth_test<D>(df, z, stored, hn::RebindMask(df, inside));
            if constexpr (DepthWrite) {
                const auto written = hn::IfThenElse(pass, z, stored);
                store_row<Aligned>(hn::LowerHalf(dh, written), dh, depth);
                store_row<Aligned>(hn::UpperHalf(dh, written), dh, depth + k_max_tile_size);
            }
            const __mmask16 bits = static_cast<__mmask16>(pass.raw);
            hn::BlendedStore(owner_id, hn::Mask256<std::uint32_t>{static_cast<__mmask8>(bits)}, duh, owner);
            hn::BlendedStore(owner_id, hn::Mask256<std::uint32_t>{static_cast<__mmask8>(bits >> 8)}, duh,
                             owner + k_max_tile_size);
            passed = static_cast<__mmask16>(passed | bits);
            depth += 2 * k_max_tile_size, owner += 2 * k_max_tile_size;
        }
    }
    return passed != 0;
}
#endif

// resolve_rect for a rectangle wider than the narrow vector: strips of one vector aligned within the
// tile's arrays (with Trimmed, only the rows of each that have pixels).
template <DepthTest D, bool DepthWrite, bool Trimmed = false, class R>
HWY_INLINE bool resolve_strips(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id,
                               const R& r) {
    const hn::ScalableTag<float> df;
    const int lanes = static_cast<int>(hn::Lanes(df));
    bool any = false;
    for (int x = r.x0; x <= r.x1;) {
        const int start = tile.x0 + ((x - tile.x0) & -lanes);  // x >= tile.x0; lanes is a power of two
        const int end = std::min(r.x1, start + lanes - 1);
        any |= resolve_strip<D, DepthWrite, true, Trimmed>(df, t, tile, buffers, id, r, start, x - start, end - start);
        x = end + 1;
    }
    return any;
}

// Out of line: few segments are this wide, and their strips' set-up would otherwise take registers
// from the narrow ones' (spilled around each call).
template <DepthTest D, bool DepthWrite, class R>
HWY_NOINLINE bool resolve_wide_segment(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id,
                                       const R& r) {
    return resolve_strips<D, DepthWrite>(t, tile, buffers, id, r);
}

// Pass one for one triangle's or segment's rectangle in the tile, r, in strips of one vector aligned
// within the tile's arrays (whose rows are wider than the tile when it is narrower than a vector:
// those lanes are never inside).
template <DepthTest D, bool DepthWrite, bool Large = false, class R>
HWY_INLINE bool resolve_rect(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id,
                             const R& r) {
    const hn::ScalableTag<float> df;
    static_assert(k_max_tile_size % (HWY_MAX_BYTES / sizeof(float)) == 0, "a row is whole vectors");
    // A rectangle within 8 aligned columns in half-width vectors when full ones are wider: on CPUs
    // that run a 512-bit operation as two 256-bit halves (AMD's Zen 4) that halves the work of the
    // most common triangles of dense meshes (the 1M sphere's frame 3-4% faster at 1 thread); where a
    // 512-bit operation costs what a 256-bit one does, the narrow one costs no more.
    constexpr int k_narrow = 8;
    constexpr int narrow = static_cast<int>(std::min<std::size_t>(k_narrow, hn::MaxLanes(df)));
    if (r.x1 - r.x0 < narrow) {
        const hn::CappedTag<float, narrow> nd;
        // A triangle's rectangle within one aligned run of `narrow` columns (most of a dense mesh's):
        // aligned vectors.
        const int aligned = tile.x0 + ((r.x0 - tile.x0) & -narrow);
        if (R::k_edges == 3 && r.x1 < aligned + narrow) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
            if (r.y1 - r.y0 >= 2)
                return resolve_row_pairs<D, DepthWrite>(t, tile, buffers, id, r, aligned, r.x0 - aligned, r.x1 - aligned);
#endif
            return resolve_strip<D, DepthWrite>(nd, t, tile, buffers, id, r, aligned, r.x0 - aligned, r.x1 - aligned);
        }
        // A triangle's that straddles two such runs, and a segment's (a thin line's, nearly all; it
        // straddles them most often): one vector per row from its first column, unaligned, rather
        // than two aligned strips, each with its own set-up. The vector stays inside the arrays'
        // rows. Each pixel is computed as in a strip: the same bytes.
        const int start = std::min(r.x0, tile.x0 + k_max_tile_size - narrow);
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
        if (r.y1 - r.y0 >= 2)
            return resolve_row_pairs<D, DepthWrite, false>(t, tile, buffers, id, r, start, r.x0 - start, r.x1 - start);
#endif
        return resolve_strip<D, DepthWrite, false>(nd, t, tile, buffers, id, r, start, r.x0 - start, r.x1 - start);
    }
    if constexpr (R::k_edges == 4) return resolve_wide_segment<D, DepthWrite>(t, tile, buffers, id, r);
    else {
        // A triangle's rectangle no wider than a full vector but across two aligned runs of it (most
        // of those 9-16 columns wide with 16 lanes: homer's): one unaligned full vector per row from
        // its first column rather than two aligned strips (homer's frame 5-6% faster at 1 thread).
        constexpr int full = static_cast<int>(hn::MaxLanes(df));
        if (full > narrow && r.x1 - r.x0 < full && r.x1 >= tile.x0 + ((r.x0 - tile.x0) & -full) + full) {
            const int start = std::min(r.x0, tile.x0 + k_max_tile_size - full);
            return resolve_strip<D, DepthWrite, false>(df, t, tile, buffers, id, r, start, r.x0 - start, r.x1 - start);
        }
        if constexpr (Large)
            if (r.x1 - r.x0 >= k_large_columns - 1 && r.y1 - r.y0 >= k_large_rows - 1)
                return resolve_strips<D, DepthWrite, true>(t, tile, buffers, id, r);
        return resolve_strips<D, DepthWrite>(t, tile, buffers, id, r);
    }
}

// A segment's record (raster/segment.hpp), which only the bins of line draws hold.
template <DepthTest D, bool DepthWrite>
HWY_INLINE bool resolve_segment(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id) {
    if (t.small_edges) [[likely]] {
        SmallSegmentRect r;
        if (!bounds_in_tile(t, tile, r)) return false;
        r.t = &t, r.origin = segment_origin(t);
        return resolve_rect<D, DepthWrite>(t, tile, buffers, id, r);
    }
    EdgeRectOf<4> r;
    if (!segment_edge_rect(t, tile, r)) return false;
    return resolve_rect<D, DepthWrite>(t, tile, buffers, id, r);
}

// Out of line, for ResolveTriangleFor: segments are drawn by bins (resolve_segment_run).
template <DepthTest D, bool DepthWrite>
HWY_NOINLINE bool resolve_segment_call(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id) {
    return resolve_segment<D, DepthWrite>(t, tile, buffers, id);
}

template <DepthTest D, bool DepthWrite, bool Large = false>
HWY_INLINE bool resolve_one(const TriangleSetup& t, PixelRect tile, TileBuffers& buffers, std::uint32_t id) {
    if (t.segment) [[unlikely]]
        return resolve_segment_call<D, DepthWrite>(t, tile, buffers, id);
    EdgeRect r;
    if (!edge_rect(t, tile, r)) return false;
    return resolve_rect<D, DepthWrite, Large>(t, tile, buffers, id, r);
}

template <DepthTest D, bool DepthWrite>
bool ResolveTriangleFor(const DepthJob& job) {
    return resolve_one<D, DepthWrite>(*job.setup, job.tile, *job.buffers, job.id);
}

// Tiny triangles: records whose rectangles in the tile are at most k_tiny x k_tiny pixels (triangles
// with small_edges, most of a dense mesh's), a group of 8 at a time (one per lane), read as two 8x8
// transposes of their first cache lines. Each lane evaluates its triangle's three edges at the
// k_tiny^2 pixels from its rectangle's corner (the same 32-bit edge integers as a strip's) and keeps
// the pixels covered as bits; what stays per triangle is its depth test at those pixels, in
// submission order, one 8-lane vector per row as a strip does it (resolve_tiny), with depth as
// depth_at. That takes the set-up of a strip and its edges off each triangle of a few pixels (about
// 270 of the ~290 instructions of a 1M-sphere record were set-up and rows). The group is prepared
// before any of its triangles is tested (it reads only the records), so the depth tests keep the
// bin's order. The others (larger, segments, edges past 32 bits) take the general path.
constexpr int k_tiny = 4;
constexpr int k_tiny_pixels = k_tiny * k_tiny;
constexpr std::uint32_t k_tiny_lane = 1u << k_tiny_pixels;         // the lane's record takes the tiny path
constexpr std::uint32_t k_tiny_across = 1u << (k_tiny_pixels + 1);  // across two aligned runs of 8 columns
using TinyTag = hn::CappedTag<std::int32_t, 8>;
struct TinyGroup {
    static constexpr int k_lanes = static_cast<int>(hn::MaxLanes(TinyTag()));
    // Per lane: bit p set when pixel p = 4 row + column of its rectangle is covered, and k_tiny_lane
    // when the lane is tiny (0 otherwise); the rectangle's first pixel as an index into the tile's
    // arrays and as (x, y); on 4-lane targets, depth at pixel p.
    alignas(64) std::uint32_t covered[k_lanes];
    alignas(64) std::int32_t corner[k_lanes];
    alignas(64) std::int32_t x[k_lanes], y[k_lanes];
    alignas(64) float z[k_tiny_pixels][k_lanes];
};

// Whether this target tests a tiny triangle's rows in 8-lane vectors (AVX2 and AVX-512), as the strips
// do, or one pixel at a time from depths the group computed (4-lane targets: SSE4, scalar).
constexpr bool k_tiny_rows = hn::MaxLanes(hn::CappedTag<float, 8>()) == 8;

#if HWY_TARGET != HWY_SCALAR
// r[i] lane j into out[j] lane i: eight 8-lane vectors of 32-bit words transposed (interleaving words,
// then pairs, then the 128-bit halves).
template <class DI>
HWY_INLINE void transpose_8x8(DI di, const hn::Vec<DI> (&r)[8], hn::Vec<DI>* out) {
    const hn::Repartition<std::int64_t, DI> dw;
    hn::Vec<decltype(dw)> t[8];
    for (int i = 0; i < 8; i += 2) {
        t[i] = hn::BitCast(dw, hn::InterleaveLower(di, r[i], r[i + 1]));
        t[i + 1] = hn::BitCast(dw, hn::InterleaveUpper(di, r[i], r[i + 1]));
    }
    hn::Vec<DI> u[8];  // u[4 q + k]: word k (and k + 4, upper half) of records 4q .. 4q + 3
    for (int q = 0; q < 2; ++q) {
        u[4 * q + 0] = hn::BitCast(di, hn::InterleaveLower(dw, t[4 * q], t[4 * q + 2]));
        u[4 * q + 1] = hn::BitCast(di, hn::InterleaveUpper(dw, t[4 * q], t[4 * q + 2]));
        u[4 * q + 2] = hn::BitCast(di, hn::InterleaveLower(dw, t[4 * q + 1], t[4 * q + 3]));
        u[4 * q + 3] = hn::BitCast(di, hn::InterleaveUpper(dw, t[4 * q + 1], t[4 * q + 3]));
    }
    for (int k = 0; k < 4; ++k) {
        out[k] = hn::ConcatLowerLower(di, u[4 + k], u[k]);
        out[k + 4] = hn::ConcatUpperUpper(di, u[4 + k], u[k]);
    }
}
#endif

// Records [n, n + lanes) of the bin, of which `valid` are there (lanes past them repeat the last).
HWY_INLINE void prepare_tiny_group(const TriangleSetup* records, std::size_t valid, PixelRect tile, TinyGroup& g) {
    const TinyTag di;
    const hn::RebindToUnsigned<TinyTag> du;
    const hn::Rebind<float, TinyTag> df;
    using VI = hn::Vec<TinyTag>;
    static_assert(sizeof(TriangleSetup) % sizeof(std::int32_t) == 0 && offsetof(TriangleSetup, e0) % 8 == 0);
    constexpr int k_words = sizeof(TriangleSetup) / sizeof(std::int32_t);
    const auto* words = reinterpret_cast<const std::int32_t*>(records);
    const VI index = hn::Mul(hn::Min(hn::Iota(di, 0), hn::Set(di, static_cast<std::int32_t>(valid) - 1)),
                             hn::Set(di, k_words));
    // The record's first 16 words (edges and bounds) in lanes: with 8 lanes, two 8x8 transposes of
    // whole rows (the records' first cache lines read as ordinary loads); else gathered.
    static_assert(offsetof(TriangleSetup, max_y) < 16 * sizeof(std::int32_t));
    VI first_words[16];
#if HWY_TARGET != HWY_SCALAR
    if constexpr (k_tiny_rows) {
        for (int half = 0; half < 2; ++half) {
            VI r[8];
            for (int i = 0; i < 8; ++i)
                r[i] = hn::Load(di, words + std::min<std::size_t>(i, valid - 1) * k_words + 8 * half);
            transpose_8x8(di, r, first_words + 8 * half);
        }
    } else
#endif
    {
        for (int w = 0; w < 16; ++w) first_words[w] = hn::GatherIndex(di, words + w, index);
    }
    const auto field = [&](std::size_t offset) {
        return offset < 16 * sizeof(std::int32_t) ? first_words[offset / 4] : hn::GatherIndex(di, words + offset / 4, index);
    };
    const auto float_field = [&](std::size_t offset) { return hn::BitCast(df, field(offset)); };
    const VI min_x = field(offsetof(TriangleSetup, min_x)), min_y = field(offsetof(TriangleSetup, min_y));
    const VI x0 = hn::Max(min_x, hn::Set(di, tile.x0)), y0 = hn::Max(min_y, hn::Set(di, tile.y0));
    const VI w = hn::Sub(hn::Min(field(offsetof(TriangleSetup, max_x)), hn::Set(di, tile.x1 - 1)), x0);
    const VI h = hn::Sub(hn::Min(field(offsetof(TriangleSetup, max_y)), hn::Set(di, tile.y1 - 1)), y0);
    // Rectangles within k_tiny on both sides (an empty one, w or h < 0, is not: its record takes the
    // general path, which finds it empty). Whether the record is a triangle's with small_edges is
    // asked per record (tiny_record), from its second cache line, which the depth test reads anyway.
    const auto small = hn::BitCast(du, hn::Or(w, h));
    auto tiny = hn::RebindMask(di, hn::Lt(small, hn::Set(du, k_tiny)));
    // With rows in vectors: whether the rectangle is across two aligned runs of 8 columns (its rows are
    // then unaligned vectors from its first column).
    const auto across = hn::RebindMask(du, hn::Gt(hn::Add(hn::And(hn::Sub(x0, hn::Set(di, tile.x0)), hn::Set(di, 7)), w),
                                                  hn::Set(di, 7)));
    if (hn::AllFalse(di, tiny)) {  // a group of larger triangles (small meshes): nothing more to do
        hn::Store(hn::Zero(du), du, g.covered);
        return;
    }
    // The rectangle's pixels: w + 1 columns in each of h + 1 rows of four bits.
    const auto one = hn::Set(du, 1);
    const auto columns = hn::Sub((one << hn::BitCast(du, hn::Add(w, hn::Set(di, 1)))), one);
    const auto rows = hn::And(hn::Sub((one << hn::BitCast(du, hn::ShiftLeft<2>(hn::Add(h, hn::Set(di, 1))))), one),
                              hn::Set(du, 0x1111u));
    const auto in_rect = hn::Mul(columns, rows);
    // Each edge at the rectangle's corner, from the record's first column and row (exact in 32 bits
    // over the bounds, by small_edges; lanes that are not tiny compute what they may, and are not used).
    const VI dx = hn::Sub(x0, min_x), dy = hn::Sub(y0, min_y);
    hn::Vec<decltype(du)> e[3], a[3], b[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = hn::BitCast(du, field(offsetof(TriangleSetup, a) + 4 * k));
        b[k] = hn::BitCast(du, field(offsetof(TriangleSetup, b) + 4 * k));
        e[k] = hn::Add(hn::BitCast(du, field(offsetof(TriangleSetup, e0) + 8 * k)),
                       hn::Add(hn::Mul(a[k], hn::BitCast(du, dx)), hn::Mul(b[k], hn::BitCast(du, dy))));
    }
    // Pixel p is inside where no edge is negative: bit p.
    auto inside = hn::Zero(du);
    hn::Vec<decltype(du)> row[3] = {e[0], e[1], e[2]};
    for (int r = 0; r < k_tiny; ++r) {
        hn::Vec<decltype(du)> at[3] = {row[0], row[1], row[2]};
        for (int c = 0; c < k_tiny; ++c) {
            const VI outside = hn::BitCast(di, hn::Or(hn::Or(at[0], at[1]), at[2]));
            inside = hn::Or(inside, hn::IfThenZeroElse(hn::RebindMask(du, hn::Lt(outside, hn::Zero(di))),
                                                       hn::Set(du, 1u << (k_tiny * r + c))));
            for (int k = 0; k < 3; ++k) at[k] = hn::Add(at[k], a[k]);
        }
        for (int k = 0; k < 3; ++k) row[k] = hn::Add(row[k], b[k]);
    }
    const auto flags = hn::IfThenElse(across, hn::Set(du, k_tiny_lane | k_tiny_across), hn::Set(du, k_tiny_lane));
    const auto covered = hn::IfThenElseZero(hn::RebindMask(du, tiny), hn::Or(hn::And(inside, in_rect), flags));
    hn::Store(covered, du, g.covered);
    hn::Store(hn::Add(hn::Mul(hn::Sub(y0, hn::Set(di, tile.y0)), hn::Set(di, k_max_tile_size)), hn::Sub(x0, hn::Set(di, tile.x0))),
              di, g.corner);
    hn::Store(x0, di, g.x);
    hn::Store(y0, di, g.y);
    if constexpr (!k_tiny_rows) {
        // Depth as depth_at: z0 + dzdx dx + dzdy dy, dx = (x + 0.5) - x0 and dy likewise, clamped.
        const auto half = hn::Set(df, 0.5f);
        const auto vx0 = float_field(offsetof(TriangleSetup, x0)), vy0 = float_field(offsetof(TriangleSetup, y0));
        const auto z0 = float_field(offsetof(TriangleSetup, z0)), dzdx = float_field(offsetof(TriangleSetup, dzdx));
        const auto dzdy = float_field(offsetof(TriangleSetup, dzdy));
        hn::Vec<decltype(df)> z_x[k_tiny];
        for (int c = 0; c < k_tiny; ++c)
            z_x[c] = hn::Add(z0, hn::Mul(dzdx, hn::Sub(hn::Add(hn::ConvertTo(df, hn::Add(x0, hn::Set(di, c))), half), vx0)));
        for (int r = 0; r < k_tiny; ++r) {
            const auto z_y = hn::Mul(dzdy, hn::Sub(hn::Add(hn::ConvertTo(df, hn::Add(y0, hn::Set(di, r))), half), vy0));
            for (int c = 0; c < k_tiny; ++c) hn::Store(clamp_depth(df, hn::Add(z_x[c], z_y)), df, g.z[r * k_tiny + c]);
        }
    }
}

// A triangle's record whose edges fit 32 bits over its bounds: small_edges and not segment, read as
// one 16-bit word (bool is one byte, 0 or 1).
HWY_INLINE bool tiny_record(const TriangleSetup& t) {
    static_assert(offsetof(TriangleSetup, segment) == offsetof(TriangleSetup, small_edges) + 1 && sizeof(bool) == 1);
    std::uint16_t flags;
    std::memcpy(&flags, &t.small_edges, sizeof(flags));
    return flags == (std::endian::native == std::endian::little ? 1 : 0x100);
}

// A tiny triangle's rows as the strips draw them: the 8-lane vector of the tile's arrays that holds
// each (aligned, or from its first column when it is across two aligned runs, the vector then kept
// inside the arrays' row), its pixels `shift` lanes in, depth as depth_at, and the rows past the
// rectangle (up to four) loaded and stored back unchanged (past the tile, in the arrays' spare rows).
template <DepthTest D, bool DepthWrite, bool Aligned>
HWY_INLINE bool resolve_tiny_rows(const TriangleSetup& t, const TinyGroup& g, int lane, TileBuffers& buffers,
                                  std::uint32_t id, int shift) {
    static_assert(k_tiny - 1 <= TileBuffers::k_rows - k_max_tile_size, "a tiny rectangle's rows are in the arrays");
    const hn::CappedTag<float, 8> df;
    const hn::RebindToUnsigned<decltype(df)> du;
    const std::uint32_t covered = g.covered[lane];
    float* depth = buffers.depth + (g.corner[lane] - shift);
    std::uint32_t* owner = buffers.owner + (g.corner[lane] - shift);
    const auto dx = hn::Sub(hn::Add(hn::Iota(df, static_cast<float>(g.x[lane] - shift)), hn::Set(df, 0.5f)),
                            hn::Set(df, t.x0));
    const auto z_x = hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.dzdx), dx));
    const auto dzdy = hn::Set(df, t.dzdy);
    const auto owner_id = hn::Set(du, id);
    const auto row = [&](int r) {
        const float dy = (static_cast<float>(g.y[lane] + r) + 0.5f) - t.y0;
        const auto z = clamp_depth(df, hn::Add(z_x, hn::Mul(dzdy, hn::Set(df, dy))));
        const std::uint8_t bits[8] = {static_cast<std::uint8_t>(((covered >> (k_tiny * r)) & 0xf) << shift)};
        const auto stored = load_row<Aligned>(df, depth + r * k_max_tile_size);
        const auto pass = depth_test<D>(df, z, stored, hn::LoadMaskBits(df, bits));
        if constexpr (DepthWrite) store_row<Aligned>(hn::IfThenElse(pass, z, stored), df, depth + r * k_max_tile_size);
        hn::BlendedStore(owner_id, hn::RebindMask(du, pass), du, owner + r * k_max_tile_size);
        return pass;
    };
    auto passed = hn::Or(row(0), row(1));
    if (covered & 0xff00u) passed = hn::Or(passed, hn::Or(row(2), row(3)));
    return !hn::AllFalse(df, passed);
}

// The depth test of tiny triangle `lane` of a group at the pixels it covers, as resolve_depth_reference.
template <DepthTest D, bool DepthWrite>
HWY_INLINE bool resolve_tiny(const TriangleSetup& t, const TinyGroup& g, int lane, TileBuffers& buffers,
                             std::uint32_t id) {
    const std::uint32_t covered = g.covered[lane];
    if constexpr (k_tiny_rows) {
        const int column = g.corner[lane] & (k_max_tile_size - 1);
        if (covered & k_tiny_across) [[unlikely]] {
            const int start = std::min(column, k_max_tile_size - 8);
            return resolve_tiny_rows<D, DepthWrite, false>(t, g, lane, buffers, id, column - start);
        }
        return resolve_tiny_rows<D, DepthWrite, true>(t, g, lane, buffers, id, column & 7);
    } else {
        (void)t;
        float* depth = buffers.depth + g.corner[lane];
        std::uint32_t* owner = buffers.owner + g.corner[lane];
        std::uint32_t any = 0;
        for (std::uint32_t m = covered & (k_tiny_lane - 1); m != 0; m &= m - 1) {
            const int p = std::countr_zero(m);
            const int at = (p / k_tiny) * k_max_tile_size + p % k_tiny;
            const float z = g.z[p][lane], stored = depth[at];
            // Chosen by masks, not branches: whether a pixel passes is as good as random.
            const std::uint32_t keep = 0u - static_cast<std::uint32_t>(depth_passes<D>(z, stored));
            if constexpr (DepthWrite)
                depth[at] = std::bit_cast<float>((std::bit_cast<std::uint32_t>(z) & keep) |
                                                 (std::bit_cast<std::uint32_t>(stored) & ~keep));
            owner[at] = (id & keep) | (owner[at] & ~keep);
            any |= keep;
        }
        return any != 0;
    }
}

// A tile's bin in order: each triangle that passes somewhere is appended to buffers.triangles, and its
// index there is its owner id. The records are read front to back, but each bin is a new stream the
// hardware prefetcher has yet to learn: they are fetched a few triangles ahead.
constexpr std::size_t k_record_distance = 12;

// The run of segment records from n on (a line draw's bin is nearly all segments), in a loop of its
// own: the segment's set-up inlined, its constants kept across records, no call per record. Returns
// the first record after the run; `id` is the next owner id, as in ResolveBinFor.
template <DepthTest D, bool DepthWrite>
HWY_NOINLINE std::size_t resolve_segment_run(const TriangleSetup* records, std::size_t n, std::size_t count,
                                             PixelRect tile, TileBuffers& buffers, const TriangleSetup** listed,
                                             std::uint32_t& id) {
    std::uint32_t next = id;
    for (; n < count && records[n].segment; ++n) {
        if (n + k_record_distance < count) prefetch_record(records + n + k_record_distance);
        const TriangleSetup& t = records[n];
        const bool any = resolve_segment<D, DepthWrite>(t, tile, buffers, next);
        *listed++ = &t;
        listed -= !any;
        next += any;
    }
    id = next;
    return n;
}

// Triangles' records are read a group of TinyGroup::k_lanes at a time (prepare_tiny_group), fetched
// further ahead; a run of segments goes to resolve_segment_run.
template <DepthTest D, bool DepthWrite, bool Large = false>
void ResolveBinFor(const TriangleSetup* records, std::size_t count, PixelRect tile, TileBuffers& buffers) {
    constexpr std::size_t k_group_distance = 32;
    constexpr std::size_t k_lanes = TinyGroup::k_lanes;
    const std::size_t first = buffers.triangles.size();
    buffers.triangles.resize(first + count);
    const TriangleSetup** listed = buffers.triangles.data() + first;
    std::uint32_t id = static_cast<std::uint32_t>(first);
    TinyGroup group;
    for (std::size_t n0 = 0; n0 < count;) {
        if (records[n0].segment) [[unlikely]] {
            n0 = resolve_segment_run<D, DepthWrite>(records, n0, count, tile, buffers, listed + (id - first), id);
            continue;
        }
        const std::size_t valid = std::min(k_lanes, count - n0);
        prepare_tiny_group(records + n0, valid, tile, group);
        for (int lane = 0; lane < static_cast<int>(valid); ++lane) {
            const std::size_t n = n0 + static_cast<std::size_t>(lane);
            // Past the bin's end too: the caller hands a bin over a piece at a time, and the next
            // piece's records follow (a prefetch past the allocation does nothing).
            prefetch_record(records + n + k_group_distance);
            const TriangleSetup& t = records[n];
            const bool any = group.covered[lane] && tiny_record(t) ? resolve_tiny<D, DepthWrite>(t, group, lane, buffers, id)
                                                                   : resolve_one<D, DepthWrite, Large>(t, tile, buffers, id);
            listed[id - first] = &t;
            id += any;
        }
        n0 += valid;
    }
    buffers.triangles.resize(id);
}

// Marks the pixels some triangle owns in `covered` (see TileBuffers::end), and with First the lowest
// owner in first_owner.
template <bool First>
HWY_INLINE void find_owned_pixels_of(TileBuffers& buffers, PixelRect tile) {
    const hn::ScalableTag<std::uint32_t> du;
    const int lanes = static_cast<int>(hn::Lanes(du));
    const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
    const auto none = hn::Set(du, TileBuffers::k_none);
    auto first = none;  // the lowest owner (k_none is above every id), or lower: see first_owner
    for (int row = 0; row < height; ++row) {
        std::uint64_t bits = 0;
        for (int i = 0; i < width; i += lanes) {
            std::uint8_t lane_bits[8] = {};
            const auto owner = hn::Load(du, buffers.owner + row * k_max_tile_size + i);
            if constexpr (First) first = hn::Min(first, owner);
            hn::StoreMaskBits(du, hn::Ne(owner, none), lane_bits);
            std::uint64_t word;
            std::memcpy(&word, lane_bits, sizeof(word));
            bits |= word << i;
        }
        // Lanes past the tile's width may hold anything (begin() sets the tile's columns only).
        buffers.covered[row] = width >= 64 ? bits : bits & ((std::uint64_t{1} << width) - 1);
    }
    if constexpr (First) {
        HWY_ALIGN std::uint32_t lane[hn::MaxLanes(du)];
        hn::Store(first, du, lane);
        buffers.first_owner = *std::min_element(lane, lane + lanes);
    } else {
        buffers.first_owner = 0;
    }
}

// The lowest owner is looked for in tiles of many listed triangles (a dense mesh's), where the
// records it saves cost more than the search; in the others first_owner is 0.
constexpr std::size_t k_find_first_owner = 64;

void FindOwnedPixels(TileBuffers& buffers, PixelRect tile) {
    if (buffers.triangles.size() >= k_find_first_owner) return find_owned_pixels_of<true>(buffers, tile);
    find_owned_pixels_of<false>(buffers, tile);
}

// The largest depth of the tile (tile_depth_ceiling): whole vectors of each row, the lanes past the
// tile's width (which may hold anything) set to -infinity. Max may keep or drop a NaN: either is what
// tile_depth_ceiling allows.
float TileDepthCeiling(const TileBuffers& buffers, PixelRect tile) {
    const hn::ScalableTag<float> df;
    const int lanes = static_cast<int>(hn::Lanes(df));
    const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
    const auto none = hn::Set(df, -std::numeric_limits<float>::infinity());
    auto m0 = none, m1 = none;  // two chains: a row of 64 is 4 vectors on AVX-512
    for (int row = 0; row < height; ++row) {
        const float* d = buffers.depth + row * k_max_tile_size;
        int i = 0;
        for (; i + 2 * lanes <= width; i += 2 * lanes) {
            m0 = hn::Max(m0, hn::Load(df, d + i));
            m1 = hn::Max(m1, hn::Load(df, d + i + lanes));
        }
        for (; i < width; i += lanes) m0 = hn::Max(m0, hn::IfThenElse(hn::FirstN(df, static_cast<std::size_t>(width - i)), hn::Load(df, d + i), none));
    }
    return hn::GetLane(hn::MaxOfLanes(df, hn::Max(m0, m1)));
}

// This target's kernels for a depth test and write flag (never, which no tile draws: ones that do nothing).
ResolveTriangleKernel ChooseResolveTriangle(DepthTest test, bool write) {
    ResolveTriangleKernel kernel = [](const DepthJob&) { return false; };
    auto with_write = [&]<DepthTest D>() {
        kernel = write ? &ResolveTriangleFor<D, true> : &ResolveTriangleFor<D, false>;
    };
    with_depth_test(test, with_write);
    return kernel;
}
ResolveBinKernel ChooseResolveBin(DepthTest test, bool write, bool large) {
    ResolveBinKernel kernel = [](const TriangleSetup*, std::size_t, PixelRect, TileBuffers&) {};
    auto with_write = [&]<DepthTest D>() {
        kernel = write ? &ResolveBinFor<D, true> : &ResolveBinFor<D, false>;
        if constexpr (D == DepthTest::less || D == DepthTest::lequal)
            if (write && large) kernel = &ResolveBinFor<D, true, true>;
    };
    with_depth_test(test, with_write);
    return kernel;
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(ChooseResolveTriangle);
HWY_EXPORT(ChooseResolveBin);
HWY_EXPORT(FindOwnedPixels);
HWY_EXPORT(TileDepthCeiling);
float tile_depth_ceiling(const TileBuffers& buffers, PixelRect tile) {
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(TileDepthCeiling)(buffers, tile);
    return tile_depth_ceiling_reference(buffers, tile);
}
void find_owned_pixels(TileBuffers& buffers, PixelRect tile) {
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(FindOwnedPixels)(buffers, tile);
    find_owned_pixels_reference(buffers, tile);
}

ResolveTriangleKernel resolve_triangle_kernel(DepthTest test, bool write) {
    ResolveTriangleKernel kernel = [](const DepthJob&) { return false; };
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(ChooseResolveTriangle)(test, write);
    auto with_write = [&]<DepthTest D>() {
        kernel = write ? &resolve_triangle_reference<D, true> : &resolve_triangle_reference<D, false>;
    };
    with_depth_test(test, with_write);
    return kernel;
}

// The scalar specification of a bin: resolve_triangle_reference per triangle, ids in listing order.
template <DepthTest D, bool DepthWrite>
void resolve_bin_reference(const TriangleSetup* records, std::size_t count, PixelRect tile, TileBuffers& buffers) {
    for (std::size_t n = 0; n < count; ++n) {
        const auto id = static_cast<std::uint32_t>(buffers.triangles.size());
        if (resolve_triangle_reference<D, DepthWrite>({&records[n], tile, &buffers, id, D, DepthWrite}))
            buffers.triangles.push_back(&records[n]);
    }
}

ResolveBinKernel resolve_bin_kernel(DepthTest test, bool write, bool large) {
    ResolveBinKernel kernel = [](const TriangleSetup*, std::size_t, PixelRect, TileBuffers&) {};
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(ChooseResolveBin)(test, write, large);
    auto with_write = [&]<DepthTest D>() {
        kernel = write ? &resolve_bin_reference<D, true> : &resolve_bin_reference<D, false>;
    };
    with_depth_test(test, with_write);
    return kernel;
}

bool resolve_triangle(const DepthJob& job) { return resolve_triangle_kernel(job.test, job.write)(job); }

}  // namespace facet::detail
#endif
