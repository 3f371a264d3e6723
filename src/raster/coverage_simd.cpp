// facet raster: the SIMD coverage kernel, compiled once per ISA by Highway (foreach_target) and
// dispatched at run time. It evaluates the edge functions of the edges that cross a rectangle at
// every pixel, N pixels at a time, in 32-bit integers (coverage.cpp proves they fit): exact, so every
// ISA gives the same bits as the scalar specification in coverage.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/coverage_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstring>

#include "raster/coverage.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// K edges: 3 for a triangle's, 4 when a segment's four cross the rectangle.
template <int K>
bool CoverRowsOf(const CrossingEdges& edges, std::uint64_t* rows) {
    const hn::ScalableTag<std::int32_t> d;
    const int lanes = static_cast<int>(hn::Lanes(d));
    using V = hn::Vec<decltype(d)>;
    const V iota = hn::Iota(d, 0);
    V a_iota[K];
    std::uint32_t e[K], a[K], b[K];  // unsigned: wrapping arithmetic in lanes past the rectangle
    for (int k = 0; k < K; ++k) {
        // Missing edges are e = a = b = 0, which never sets a sign bit.
        const bool used = k < edges.count;
        e[k] = used ? static_cast<std::uint32_t>(edges.e[k]) : 0;
        a[k] = used ? static_cast<std::uint32_t>(edges.a[k]) : 0;
        b[k] = used ? static_cast<std::uint32_t>(edges.b[k]) : 0;
        a_iota[k] = hn::Mul(hn::Set(d, static_cast<std::int32_t>(a[k])), iota);
    }
    const std::uint64_t width_mask = edges.width >= 64 ? ~0ull : (1ull << edges.width) - 1;
    bool any = false;
    for (int row = 0; row < edges.height; ++row) {
        std::uint64_t mask = 0;
        for (int x = 0; x < edges.width; x += lanes) {
            const std::uint32_t ux = static_cast<std::uint32_t>(x);
            V v = hn::Zero(d);
            for (int k = 0; k < K; ++k)
                v = hn::Or(v, hn::Add(hn::Set(d, static_cast<std::int32_t>(e[k] + a[k] * ux)), a_iota[k]));
            // Covered where every edge function is >= 0: no sign bit in their OR.
            std::uint8_t bits[8] = {};
            hn::StoreMaskBits(d, hn::Not(hn::Lt(v, hn::Zero(d))), bits);
            std::uint64_t word = 0;
            std::memcpy(&word, bits, sizeof(word));
            mask |= word << x;
        }
        mask &= width_mask;
        any |= mask != 0;
        rows[row] = mask << edges.shift;
        for (int k = 0; k < K; ++k) e[k] += b[k];
    }
    return any;
}

bool CoverRows(const CrossingEdges& edges, std::uint64_t* rows) {
    return edges.count > 3 ? CoverRowsOf<4>(edges, rows) : CoverRowsOf<3>(edges, rows);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace facet::detail {
HWY_EXPORT(CoverRows);

bool cover_rows_simd(const CrossingEdges& edges, std::uint64_t* rows) {
    return HWY_DYNAMIC_DISPATCH(CoverRows)(edges, rows);
}
}  // namespace facet::detail
#endif
