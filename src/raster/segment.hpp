// facet raster: a line segment's record. In: a segment's snapped ends and the offsets of its quad's
// corners (src/bin/points_lines.cpp decides them). A segment is one TriangleSetup record with
// `segment` set: its four edges, in the 48 bytes where a triangle keeps its three, and the triangle's
// bounds, attribute planes, vertices and flags, which the tiles and the shading stage read as they
// read a triangle's. Made one at a time (segment_record, the specification) or in SIMD batches
// (setup_segment_lanes, segment_simd.cpp). Does not shade.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "facet/detail/frame.hpp"
#include "facet/detail/segment_edges.hpp"  // SegmentEdges and its accessors
#include "setup/setup.hpp"

namespace facet::detail {

// A segment's end at screen vertex v: its quad's corners left and right of the segment, v +- offset
// (1/256 pixel).
struct SegmentEnd {
    std::int32_t ox, oy;
    bool operator==(const SegmentEnd&) const = default;
};

// std::llround (halves away from zero) for |x| < 2^52 without the library call (a tenth of a
// segment's front end): x - trunc(x) is exact, and the cast truncates.
inline std::int64_t round_half_away(double x) {
    const auto i = static_cast<std::int64_t>(x);
    const double f = x - static_cast<double>(i);
    return i + (f >= 0.5) - (f <= -0.5);
}

// A square end of segment a -> b (a != b) for half-width h (pixels): the corners at h on either side
// along the unit normal n = (-dy, dx) / length, rounded to 1/256 pixel.
inline SegmentEnd square_end(const ScreenVertex& a, const ScreenVertex& b, double h) {
    const double dx = static_cast<double>(b.x - a.x), dy = static_cast<double>(b.y - a.y);
    const double length = std::sqrt(dx * dx + dy * dy);
    return {static_cast<std::int32_t>(round_half_away(-dy / length * h * k_subpixel_one)),
            static_cast<std::int32_t>(round_half_away(dx / length * h * k_subpixel_one))};
}

enum class SegmentResult {
    record,     // t is the segment's record
    triangles,  // the quad is not strictly convex, or its edges do not fit 32 bits: draw it as two triangles
    empty,      // no pixel centre inside the scissor's bounds
};

// Segment a -> b as one record: the quad a + e0, a - e0, b - e1, b + e1 by its four edges (pixel
// centres inside all four), depth and attributes interpolated along the segment (vertex ref_a at a,
// ref_b at b). A quad that is not strictly convex (a short segment between sharp mitres, or one too
// thin to have an inside) or whose edges do not fit the record's 32 bits (segments tens of thousands of
// pixels long) is left to the caller as two triangles; a strictly convex quad covers the same pixels
// either way (its outer edges are the triangles', and the top-left rule gives the diagonal's pixels
// to one of them), but for pixel centres exactly on a corner. a != b. `out_a` and `out_b` (an
// anti-aliased segment's free ends) move the quad's ends past a and b, outward along the segment:
// its corners at a are a - out_a +- e0, at b b + out_b +- e1; the planes stay those of a -> b.
SegmentResult segment_record(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1,
                             std::uint32_t ref_a, std::uint32_t ref_b, const PixelRect& scissor, TriangleSetup& t,
                             SegmentEnd out_a = {}, SegmentEnd out_b = {});

// Up to k_capacity segments, in submission order, to be made into records together.
struct SegmentBatch {
    static constexpr int k_capacity = SetupBatch::k_capacity;
    ScreenVertex a[k_capacity], b[k_capacity];
    std::int32_t ox0[k_capacity], oy0[k_capacity], ox1[k_capacity], oy1[k_capacity];  // the ends' SegmentEnd
    std::int32_t square[k_capacity];  // non-zero: both ends are square_end(a, b, half_width), the offsets unused
    std::uint32_t ref_a[k_capacity], ref_b[k_capacity];
    double half_width = 0;
    int count = 0;
};

// segment_record on each segment of the batch (its ends as given, or square ones) by the SIMD kernel
// of the selected ISA, bit for bit:
// lanes.keep has bit i when segment i's record is lanes' entry i (write_record), lanes.culled (here:
// left to the caller) when segment_record says `triangles`; neither bit when it says `empty`. False
// when the batch must go one by one instead: the scalar ISA is selected, or a coordinate is too large
// for the kernel's exact doubles (beyond the guard band and the widest line's offsets).
bool setup_segment_lanes(const SegmentBatch& batch, const PixelRect& scissor, SetupLanes& lanes);

// True when some edge of segment record t is negative over the whole rectangle (binning).
bool segment_rejects(const TriangleSetup& t, const PixelRect& r);

// The scalar specification of a segment's coverage within a tile: every pixel of its bounds there
// tested against the four edges. Sets out's row range as rasterize_tile does.
bool rasterize_segment_reference(const TriangleSetup& t, PixelRect tile, TileCoverage& out);

}  // namespace facet::detail
