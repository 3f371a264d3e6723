// facet raster: coverage of one set-up triangle within one tile.
// In: TriangleSetup (integer edge functions in pixel units, top-left rule folded in) and a tile.
// Out: TileCoverage, one bit per pixel. Edge values are stepped incrementally from row to row and
// each row's covered span is solved exactly with integer division, so the cost is per row, not per
// pixel. Does not shade or test depth.
#include <algorithm>

#include "facet/detail/frame.hpp"

namespace facet::detail {
namespace {

std::int64_t floor_div(std::int64_t n, std::int64_t d) {  // d > 0
    std::int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}

std::uint64_t span_mask(int lo, int hi) {  // bits lo..hi inclusive, 0 <= lo <= hi < 64
    std::uint64_t upto_hi = hi >= 63 ? ~0ull : ((1ull << (hi + 1)) - 1);
    return upto_hi & ~((1ull << lo) - 1);
}

}  // namespace

bool rasterize_tile(const TriangleSetup& t, PixelRect tile, TileCoverage& out) {
    const int x0 = std::max(tile.x0, t.min_x), x1 = std::min(tile.x1 - 1, t.max_x);
    const int y0 = std::max(tile.y0, t.min_y), y1 = std::min(tile.y1 - 1, t.max_y);
    out.first_row = y0 - tile.y0;
    out.last_row = y1 - tile.y0;
    if (x0 > x1 || y0 > y1) {
        out.last_row = out.first_row - 1;
        return false;
    }
    bool any = false;
    // Each edge's value at (0, y) is stepped incrementally from row to row; within a row the span
    // where all three are >= 0 is solved exactly.
    std::int64_t r[3];
    for (int e = 0; e < 3; ++e) r[e] = std::int64_t{t.b[e]} * y0 + t.c[e];
    for (int y = y0; y <= y1; ++y) {
        // Intersect the half-lines {x : a*x + r >= 0} of the three edges with [x0, x1].
        std::int64_t lo = x0, hi = x1;
        for (int e = 0; e < 3; ++e) {
            const std::int64_t a = t.a[e];
            if (a > 0)
                lo = std::max(lo, -floor_div(r[e], a));  // x >= ceil(-r / a)
            else if (a < 0)
                hi = std::min(hi, floor_div(r[e], -a));  // x <= floor(r / -a)
            else if (r[e] < 0)
                hi = lo - 1;
            r[e] += t.b[e];
        }
        std::uint64_t mask = 0;
        if (lo <= hi) {
            mask = span_mask(static_cast<int>(lo - tile.x0), static_cast<int>(hi - tile.x0));
            any = true;
        }
        out.rows[y - tile.y0] = mask;
    }
    return any;
}

}  // namespace facet::detail
