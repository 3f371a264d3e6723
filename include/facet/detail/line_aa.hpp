// facet internals: an anti-aliased segment's coverage of a pixel (README.md, "Anti-aliased lines").
// In: a segment record with line_aa set, whose quad src/bin/points_lines.cpp made around the band of
// half-width width / 2 + 1/2 (free ends pushed out by 1/2 pixel). Out: the coverage in [0, 1], the
// distance from the pixel centre to the nearest edge of that quad that fades, at most 1. The
// one-pass order's pixel loop (fragment.hpp) blends by it; this does not test depth nor blend.
#pragma once

#include <algorithm>
#include <cmath>

#include "facet/api.hpp"
#include "facet/detail/segment_edges.hpp"

FACET_API_BEGIN
namespace facet::detail {

// The state an anti-aliased line draw runs with: alpha blending, no depth writes (the depth test as given).
inline DrawState line_aa_state(DrawState state) {
    state.blend = Blend::alpha;
    state.depth_write = false;
    return state;
}

struct LineAaCoverage {
    SegmentEdges edges{};
    PixelIndex origin{};
    // Per edge, what turns its value into pixels of distance: 1 / |(a, b)| (a and b are in 1/256
    // pixel, the value in 1/256 pixel squared over 256); 0 for an edge that does not fade (a join's).
    double per_length[4]{};

    LineAaCoverage() = default;
    explicit LineAaCoverage(const TriangleSetup& t) : edges(segment_edges(t)), origin(segment_origin(t)) {
        for (int k = 0; k < 4; ++k) {
            const double a = edges.a[k], b = edges.b[k];
            per_length[k] = (t.line_aa >> k & 1) ? 1.0 / std::sqrt(a * a + b * b) : 0.0;
        }
    }

    // Pixel (x, y)'s coverage: exact integer edge values, then one rounding each (the same bits on
    // every ISA and thread).
    float at(int x, int y) const {
        double d = 1.0;
        for (int k = 0; k < 4; ++k)
            if (per_length[k] > 0) d = std::min(d, static_cast<double>(segment_edge_at(edges, origin, k, x, y)) * per_length[k]);
        return d > 0 ? static_cast<float>(d) : 0.0f;
    }
};

}  // namespace facet::detail
FACET_API_END
