// facet internals: the four edges of a line segment's record (src/raster/segment.hpp describes the
// record), read where the tiles test coverage and where an anti-aliased segment's shading measures
// distances (line_aa.hpp). In: a TriangleSetup with `segment` set. Does not make records.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "facet/api.hpp"
#include "facet/detail/frame.hpp"

FACET_API_BEGIN
namespace facet::detail {

// The quad's edges in pixel units, the top-left rule folded in (setup.hpp's pixel_edge): pixel
// (ix, iy) is inside when every e[k] + a[k] (ix - rx) + b[k] (iy - ry) >= 0, (rx, ry) being the
// pixel of the record's (x0, y0) (segment_origin). Relative to that pixel, not to the bounds'
// corner, so that the values fit in 32 bits for segments much longer than a tile. The record's
// small_edges says that every value over its bounds fits in 32 bits.
struct SegmentEdges {
    std::int32_t a[4], b[4], e[4];
};

static_assert(sizeof(SegmentEdges) == offsetof(TriangleSetup, min_x) && offsetof(TriangleSetup, a) == 0,
              "a segment's edges take the place of a triangle's");

inline SegmentEdges segment_edges(const TriangleSetup& t) {
    SegmentEdges s;
    std::memcpy(&s, &t, sizeof s);
    return s;
}

inline void set_segment_edges(TriangleSetup& t, const SegmentEdges& s) { std::memcpy(&t, &s, sizeof s); }

// The pixel whose corner is the record's (x0, y0): its floor, exact (x0 is a snapped coordinate / 256).
struct PixelIndex {
    int x, y;
};
inline PixelIndex segment_origin(const TriangleSetup& t) {
    const auto floor = [](float v) {
        const auto i = static_cast<int>(v);  // towards zero: one less for a negative fraction
        return i - (static_cast<float>(i) > v);
    };
    return {floor(t.x0), floor(t.y0)};
}

// Edge k of segment record t at pixel (ix, iy), exactly.
inline std::int64_t segment_edge_at(const SegmentEdges& s, PixelIndex origin, int k, std::int64_t ix, std::int64_t iy) {
    return s.e[k] + std::int64_t{s.a[k]} * (ix - origin.x) + std::int64_t{s.b[k]} * (iy - origin.y);
}

}  // namespace facet::detail
FACET_API_END
