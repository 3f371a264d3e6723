// facet raster: a line segment's record (segment.hpp) by the scalar specification, its coverage by
// the scalar specification, and the binning test. In: a segment's ends, or its TriangleSetup record.
// Out: the record, coverage bits, or whether a tile is missed.
#include "raster/segment.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>

namespace facet::detail {

SegmentResult segment_record(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1,
                             std::uint32_t ref_a, std::uint32_t ref_b, const PixelRect& scissor, TriangleSetup& t,
                             SegmentEnd out_a, SegmentEnd out_b) {
    const std::int32_t ax = a.x - out_a.ox, ay = a.y - out_a.oy, bx = b.x + out_b.ox, by = b.y + out_b.oy;
    const std::int32_t cx[4] = {ax + e0.ox, ax - e0.ox, bx - e1.ox, bx + e1.ox};
    const std::int32_t cy[4] = {ay + e0.oy, ay - e0.oy, by - e1.oy, by + e1.oy};
    // The turn at each corner: all > 0 or all < 0 when strictly convex. Square ends (e0 = e1) make a
    // parallelogram (as do ends moved out along the segment), whose four turns are one. Bitwise and selected rather than branched on: a
    // segment's direction, hence its quad's winding, is as good as random.
    const auto turn = [&](int k) {
        const int q = (k + 1) % 4, r = (k + 2) % 4;
        return std::int64_t{cx[q] - cx[k]} * (cy[r] - cy[q]) - std::int64_t{cy[q] - cy[k]} * (cx[r] - cx[q]);
    };
    bool positive = turn(0) > 0, negative = turn(0) < 0;
    if (!(e0 == e1)) {
        for (int k = 1; k < 4; ++k) {
            const std::int64_t n = turn(k);
            positive &= n > 0;
            negative &= n < 0;
        }
    }
    if (!(positive | negative)) [[unlikely]]
        return SegmentResult::triangles;
    // Counter-clockwise as setup_triangle orients triangles, so that every edge is >= 0 inside.
    const std::int32_t vx[4] = {cx[0], positive ? cx[1] : cx[3], cx[2], positive ? cx[3] : cx[1]};
    const std::int32_t vy[4] = {cy[0], positive ? cy[1] : cy[3], cy[2], positive ? cy[3] : cy[1]};
    const int min_x = std::max(first_centre(std::min(std::min(vx[0], vx[1]), std::min(vx[2], vx[3]))), scissor.x0);
    const int max_x = std::min(last_centre(std::max(std::max(vx[0], vx[1]), std::max(vx[2], vx[3]))), scissor.x1 - 1);
    const int min_y = std::max(first_centre(std::min(std::min(vy[0], vy[1]), std::min(vy[2], vy[3]))), scissor.y0);
    const int max_y = std::min(last_centre(std::max(std::max(vy[0], vy[1]), std::max(vy[2], vy[3]))), scissor.y1 - 1);
    if (min_x > max_x || min_y > max_y) return SegmentResult::empty;
    // Edges relative to the pixel of a, the planes' origin (segment_origin). They fit the lanes' 32
    // bits over the whole bounds (small_edges) when the largest value there does.
    const int ox = a.x >> k_subpixel_bits, oy = a.y >> k_subpixel_bits;
    const std::int64_t reach = std::max(std::max(ox - min_x, max_x - ox), std::max(oy - min_y, max_y - oy));
    SegmentEdges edges;
    bool fits = true, small = true;
    for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        const PixelEdge e = pixel_edge(vx[k], vy[k], vx[n], vy[n], ox, oy);
        fits &= e.at >= INT32_MIN && e.at <= INT32_MAX;
        small &= std::abs(e.at) + (std::abs(std::int64_t{e.a}) + std::abs(std::int64_t{e.b})) * reach <= INT32_MAX;
        edges.a[k] = e.a, edges.b[k] = e.b, edges.e[k] = static_cast<std::int32_t>(e.at);
    }
    if (!fits) [[unlikely]]
        return SegmentResult::triangles;
    set_segment_edges(t, edges);
    t.min_x = min_x, t.max_x = max_x, t.min_y = min_y, t.max_y = max_y;
    // The planes: f(p) = f(a) + (f(b) - f(a)) s(p), s the screen-space position along a -> b (0 at a,
    // 1 at b: the projection of p on the segment). Depth and q = 1/w are linear in s; b1 q, the
    // perspective-correct weight of b times q, is q(b) s, and vertex 2 has weight 0.
    const double dx = b.x - a.x, dy = b.y - a.y, per_length2 = k_subpixel_one / (dx * dx + dy * dy);
    const double sx = dx * per_length2, sy = dy * per_length2;  // ds per pixel
    const double dz = static_cast<double>(b.z) - a.z, dq = static_cast<double>(b.q) - a.q, qb = b.q;
    constexpr double scale = 1.0 / k_subpixel_one;
    t.x0 = static_cast<float>(a.x * scale), t.y0 = static_cast<float>(a.y * scale);
    t.z0 = a.z, t.dzdx = static_cast<float>(dz * sx), t.dzdy = static_cast<float>(dz * sy);
    t.q0 = a.q, t.dqdx = static_cast<float>(dq * sx), t.dqdy = static_cast<float>(dq * sy);
    t.dl1dx = static_cast<float>(qb * sx), t.dl1dy = static_cast<float>(qb * sy);
    t.dl2dx = 0, t.dl2dy = 0;
    t.vertex[0] = ref_a, t.vertex[1] = ref_b, t.vertex[2] = ref_b;
    t.front_facing = true;
    t.small_edges = small;
    t.segment = true;
    t.line_aa = 0;  // an anti-aliased segment's caller names its fading edges
    return SegmentResult::record;
}

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
