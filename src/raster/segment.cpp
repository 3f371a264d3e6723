// facet raster: a line segment's record (segment.hpp): its coverage by the scalar specification, and
// the binning test. In: a segment's TriangleSetup record. Out: coverage bits, or whether a tile is missed.
#include "raster/segment.hpp"

#include <algorithm>

namespace facet::detail {

bool segment_rejects(const TriangleSetup& t, const PixelRect& r) {
    const SegmentEdges s = segment_edges(t);
    const PixelIndex origin = segment_origin(t);
    for (int k = 0; k < 4; ++k) {
        // The largest value over the rectangle is at the corner the gradient points to.
        const std::int64_t x = s.a[k] > 0 ? r.x1 - 1 : r.x0, y = s.b[k] > 0 ? r.y1 - 1 : r.y0;
        if (segment_edge_at(s, origin, k, x, y) < 0) return true;
    }
    return false;
}

bool rasterize_segment_reference(const TriangleSetup& t, PixelRect tile, TileCoverage& out) {
    const int x0 = std::max(tile.x0, t.min_x), y0 = std::max(tile.y0, t.min_y);
    const int x1 = std::min(tile.x1 - 1, t.max_x), y1 = std::min(tile.y1 - 1, t.max_y);
    out.first_row = y0 - tile.y0;
    out.last_row = x0 > x1 || y0 > y1 ? out.first_row - 1 : y1 - tile.y0;
    const SegmentEdges s = segment_edges(t);
    const PixelIndex origin = segment_origin(t);
    bool any = false;
    for (int y = y0; y <= out.last_row + tile.y0; ++y) {
        std::uint64_t row = 0;
        for (int x = x0; x <= x1; ++x) {
            bool inside = true;
            for (int k = 0; k < 4; ++k) inside = inside && segment_edge_at(s, origin, k, x, y) >= 0;
            row |= std::uint64_t{inside} << (x - tile.x0);
        }
        out.rows[y - tile.y0] = row;
        any = any || row != 0;
    }
    return any;
}

}  // namespace facet::detail
