// facet raster: coverage of one set-up triangle within one tile.
// In: TriangleSetup (integer edge functions in pixel units, top-left rule folded in) and a tile.
// Out: TileCoverage, one bit per pixel. Each edge bounds every row's span from one side at
// x = floor(r / d) (or its negation), with r stepping by b from row to row; the quotient and
// remainder are stepped exactly like a Bresenham line, so after one division per edge and tile
// every row costs a few integer additions, whatever its width. Does not shade or test depth.
// That row-span algorithm is the scalar specification (rasterize_tile_reference); rasterize_tile
// drops the edges that pass everywhere in the rectangle and lets the SIMD kernel evaluate the rest
// pixel by pixel, which for the small triangles of real meshes costs far less than its divisions.
#include <algorithm>
#include <optional>

#include "facet/detail/frame.hpp"
#include "raster/coverage.hpp"
#include "raster/segment.hpp"
#include "simd/isa.hpp"

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

// floor(r / d) for r = r0 + k*b at k = 0, 1, 2, ... without dividing per step:
// keeps q = floor(r / d) and rem = r - q*d in [0, d).
struct FloorStepper {
    std::int64_t q, rem, d, step_q, step_rem;
    FloorStepper(std::int64_t r0, std::int64_t b, std::int64_t d_) : d(d_) {
        q = floor_div(r0, d);
        rem = r0 - q * d;
        step_q = floor_div(b, d);
        step_rem = b - step_q * d;
    }
    void step() {
        q += step_q;
        rem += step_rem;
        if (rem >= d) {
            rem -= d;
            ++q;
        }
    }
};

struct InclusiveRect {
    int x0, y0, x1, y1;  // first and last pixel indices
};

// The triangle's bounds within the tile, with out's row range set to them; nothing (and an empty
// row range) when they do not meet.
std::optional<InclusiveRect> overlap(const TriangleSetup& t, PixelRect tile, TileCoverage& out) {
    const InclusiveRect r{std::max(tile.x0, t.min_x), std::max(tile.y0, t.min_y), std::min(tile.x1 - 1, t.max_x),
                      std::min(tile.y1 - 1, t.max_y)};
    out.first_row = r.y0 - tile.y0;
    out.last_row = r.y1 - tile.y0;
    if (r.x0 > r.x1 || r.y0 > r.y1) {
        out.last_row = out.first_row - 1;
        return std::nullopt;
    }
    return r;
}

}  // namespace

bool rasterize_tile_reference(const TriangleSetup& t, PixelRect tile, TileCoverage& out) {
    if (t.segment) return rasterize_segment_reference(t, tile, out);
    const std::optional<InclusiveRect> rect = overlap(t, tile, out);
    if (!rect) return false;
    const int x0 = rect->x0, x1 = rect->x1, y0 = rect->y0, y1 = rect->y1;

    // Edge e holds where a*x + r(y) >= 0 with r(y) = e(0, y), the edge at column 0:
    //   a > 0:  x >= ceil(-r / a) = -floor(r / a)     (a lower bound)
    //   a < 0:  x <= floor(r / -a)                    (an upper bound)
    //   a = 0:  every x when r >= 0, none otherwise
    FloorStepper lower[3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}, upper[3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    int lower_count = 0, upper_count = 0;
    std::int64_t flat_r[3];
    std::int64_t flat_b[3];
    int flat_count = 0;
    for (int e = 0; e < 3; ++e) {
        const std::int64_t a = t.a[e], b = t.b[e], r0 = edge_at(t, e, 0, y0);
        if (a > 0)
            lower[lower_count++] = FloorStepper(r0, b, a);
        else if (a < 0)
            upper[upper_count++] = FloorStepper(r0, b, -a);
        else {
            flat_r[flat_count] = r0;
            flat_b[flat_count++] = b;
        }
    }

    bool any = false;
    for (int y = y0; y <= y1; ++y) {
        std::int64_t lo = x0, hi = x1;
        for (int i = 0; i < lower_count; ++i) {
            lo = std::max(lo, -lower[i].q);
            lower[i].step();
        }
        for (int i = 0; i < upper_count; ++i) {
            hi = std::min(hi, upper[i].q);
            upper[i].step();
        }
        for (int i = 0; i < flat_count; ++i) {
            if (flat_r[i] < 0) hi = lo - 1;
            flat_r[i] += flat_b[i];
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

bool rasterize_tile(const TriangleSetup& t, PixelRect tile, TileCoverage& out) {
    if (use_scalar_kernels()) return rasterize_tile_reference(t, tile, out);
    const std::optional<InclusiveRect> rect = overlap(t, tile, out);
    if (!rect) return false;
    const int x0 = rect->x0, x1 = rect->x1, y0 = rect->y0, y1 = rect->y1;
    CrossingEdges edges{};
    edges.width = x1 - x0 + 1;
    edges.height = y1 - y0 + 1;
    edges.shift = x0 - tile.x0;
    // Edge (first, a, b) over the rectangle, its value at (x0, y0) and its steps. Its extremes are
    // at the corners. max - min = |a| (w - 1) + |b| (h - 1) < 2 * 2^24 * 63 < 2^31, so an edge that
    // changes sign inside (min < 0 <= max) has every value in the rectangle within 32 bits. False
    // when it is negative everywhere.
    const auto add_edge = [&](std::int64_t first, std::int32_t a, std::int32_t b) {
        const std::int64_t min = first + std::min<std::int64_t>(a, 0) * (edges.width - 1) +
                                 std::min<std::int64_t>(b, 0) * (edges.height - 1);
        const std::int64_t max = first + std::max<std::int64_t>(a, 0) * (edges.width - 1) +
                                 std::max<std::int64_t>(b, 0) * (edges.height - 1);
        if (max < 0) return false;
        if (min >= 0) return true;  // inside this edge everywhere
        edges.e[edges.count] = static_cast<std::int32_t>(first);
        edges.a[edges.count] = a;
        edges.b[edges.count] = b;
        ++edges.count;
        return true;
    };
    bool inside = true;
    if (t.segment) {
        const SegmentEdges s = segment_edges(t);
        const PixelIndex origin = segment_origin(t);
        for (int k = 0; k < 4 && inside; ++k) inside = add_edge(segment_edge_at(s, origin, k, x0, y0), s.a[k], s.b[k]);
    } else {
        for (int k = 0; k < 3 && inside; ++k) inside = add_edge(edge_at(t, k, x0, y0), t.a[k], t.b[k]);
    }
    if (!inside) {  // outside some edge everywhere
        out.last_row = out.first_row - 1;
        return false;
    }
    std::uint64_t* rows = out.rows + out.first_row;
    if (edges.count == 0) {
        const std::uint64_t span = span_mask(edges.shift, edges.shift + edges.width - 1);
        std::fill(rows, rows + edges.height, span);
        return true;
    }
    return cover_rows_simd(edges, rows);
}

}  // namespace facet::detail
