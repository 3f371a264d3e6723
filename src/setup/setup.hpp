// facet setup: from a clipped triangle to a TriangleSetup.
// In: three projected, snapped vertices (geometry/project.hpp). Steps: cull by the winding the
// viewer sees, orient counter-clockwise in screen space, edge functions with the top-left rule,
// attribute planes.
// Out: TriangleSetup, or nothing when the triangle is culled, has zero area or covers no pixel centre
// (tested exactly when its bounds hold no centre or at most 3x3 of them; larger ones go on).
// setup_triangles does the same for a batch of unclipped triangles at once (setup_simd.cpp, SIMD).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

#include "facet/detail/fragment.hpp"
#include "facet/detail/front_end.hpp"

namespace facet::detail {

enum class SetupResult { ok, culled, empty };

// Pixel index range whose centres (i + 0.5) lie in [lo, hi] (fixed point). An arithmetic right
// shift is floor division by the power of two k_subpixel_one.
inline int first_centre(std::int32_t lo) { return -((k_subpixel_one / 2 - lo) >> k_subpixel_bits); }
inline int last_centre(std::int32_t hi) { return (hi - k_subpixel_one / 2) >> k_subpixel_bits; }

// Twice a screen triangle's signed area in fixed point; positive: clockwise to the viewer (screen y
// grows downward).
inline std::int64_t twice_signed_area(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) {
    return std::int64_t{b.x - a.x} * (c.y - a.y) - std::int64_t{c.x - a.x} * (b.y - a.y);
}
// Whether a triangle of that signed area is drawn under the state's culling (zero area never is);
// `front` is set to the side it shows.
inline bool kept_by_culling(std::int64_t signed_area, const DrawState& state, bool& front) {
    if (signed_area == 0) return false;
    front = (state.front_face == FrontFace::ccw) == (signed_area < 0);
    return !((state.cull == CullMode::back && !front) || (state.cull == CullMode::front && front));
}
// The pixels whose centres the vertices' bounds reach, within the scissor, inclusive (empty when
// x0 > x1 or y0 > y1): a triangle's record bounds. The minima and maxima are nested pairs: std::min of
// an initializer list compiles to branches, which mispredict.
struct CentreBounds {
    int x0, y0, x1, y1;
};
inline CentreBounds centre_bounds(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c,
                                  const PixelRect& scissor) {
    return {std::max(first_centre(std::min(a.x, std::min(b.x, c.x))), scissor.x0),
            std::max(first_centre(std::min(a.y, std::min(b.y, c.y))), scissor.y0),
            std::min(last_centre(std::max(a.x, std::max(b.x, c.x))), scissor.x1 - 1),
            std::min(last_centre(std::max(a.y, std::max(b.y, c.y))), scissor.y1 - 1)};
}

// The edge function of a -> b (snapped coordinates) in pixel units, the top-left rule folded in:
// pixel (ix, iy) is on the inside (left of a -> b in screen coordinates, y down) when
// at + a (ix - x) + b (iy - y) >= 0, exactly, `at` being its value at pixel (x, y). Every edge of a
// triangle's or a segment's record is made by it.
//
// E(p) = A (px - ax) + B (py - ay), positive inside. A pixel centre exactly on an edge belongs to
// the triangle only for a top edge (horizontal, inside below) or a left edge (inside to the right).
// With p = 256 i + 128 per axis, E = 256 (A (ix - x) + B (iy - y)) + E(centre of (x, y)), and for
// integers 256 k + c >= 0  <=>  k + floor(c / 256) >= 0, which turns E into pixel units exactly.
// Snapped coordinates are below 2^22 in magnitude, so A and B fit in 32 bits and `at` needs 64.
struct PixelEdge {
    std::int32_t a, b;
    std::int64_t at;
};
inline PixelEdge pixel_edge(std::int32_t ax, std::int32_t ay, std::int32_t bx, std::int32_t by, int x, int y) {
    const std::int32_t A = ay - by, B = bx - ax;
    // Bitwise, not short-circuit: the edge directions are random, so a branch here mispredicts often.
    const bool top_left = (A > 0) | ((A == 0) & (B > 0));
    const std::int64_t centre_x = std::int64_t{x} * k_subpixel_one + k_subpixel_one / 2 - ax;
    const std::int64_t centre_y = std::int64_t{y} * k_subpixel_one + k_subpixel_one / 2 - ay;
    const std::int64_t c = A * centre_x + B * centre_y + (static_cast<std::int64_t>(top_left) - 1);
    return {A, B, c >> k_subpixel_bits};  // the arithmetic shift is floor division by 256
}

// Bounds up to this many pixels wide and tall are tested pixel by pixel in setup. A triangle there
// that covers none of their centres is empty: most such triangles are a dense mesh's smallest (12%
// of the records of the 1M sphere at 1920x1080), and every record costs more to bin and to
// resolve in a tile than the nine centres cost to test; larger bounds are left to the tiles.
constexpr int k_small_bounds = 3;
// True when t's bounds are within k_small_bounds pixels on both axes and t covers none of their
// centres. Needs t's bounds and edges.
bool covers_no_centre_of_small_bounds(const TriangleSetup& t);

// `ref` names each vertex's varyings (a ClipVertices index, or k_clipped_bit | extras index).
SetupResult setup_triangle(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], const FrontEndParams& params,
                           TriangleSetup& out);

// The lowest value depth_at (fragment.hpp: the depth pass's depth, clamped) gives t at any pixel of its
// bounds, or -infinity: the depth floor of a record (FrontEndChunk::depth_floors). Each operation of
// depth_at rounds monotonically in x and in y, so that is its value at the corner of the bounds the
// depth plane falls toward: exact, with no margin. -infinity for a segment's record (its depth is not
// depth_at's) and for gradients so steep that a sum could reach infinity (inf - inf is not monotonic;
// below 1e30, offsets under 2^15 pixels keep every term finite).
inline float lowest_depth(const TriangleSetup& t) {
    constexpr float k_none = -std::numeric_limits<float>::infinity(), k_steep = 1e30f;
    if (t.segment || !(std::fabs(t.dzdx) < k_steep) || !(std::fabs(t.dzdy) < k_steep) || !(std::fabs(t.z0) < k_steep))
        return k_none;
    const float z = depth_at(t, t.dzdx < 0 ? t.max_x : t.min_x, t.dzdy < 0 ? t.max_y : t.min_y);
    return z >= 0 ? z : k_none;
}

// Up to k_capacity triangles, in submission order, to be set up together. The vertices are stored per
// corner (v[k][i] is corner k of triangle i) so that the kernel loads each corner of a group of
// triangles with one deinterleaving load.
struct SetupBatch {
    static constexpr int k_capacity = 16;  // a multiple of every ISA's number of double lanes
    ScreenVertex v[3][k_capacity];
    std::uint32_t ref[3][k_capacity];
    int count = 0;
};

struct BatchSetupCounts {
    int written;  // records written
    int culled;   // triangles culled (zero area or facing away), as SetupResult::culled
};

// Sets up triangles [0, batch.count) as setup_triangle does each, bit for bit, and writes the records of
// those that survive to out[0, written) in batch order. `out` has room for batch.count records.
BatchSetupCounts setup_triangles(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out);

// The two halves of setup_triangles, for a caller that writes each record straight to where it goes
// (the front end: into its tile's bin) rather than to an array it then copies from.
// The SIMD kernel's results, one entry per batch triangle (setup_simd.cpp), read by write_record.
// The record is 32 four-byte words; the kernel stores them already interleaved, four words of each
// triangle to a 16-byte unit (unit[g][i] is words 4g..4g+3 of triangle i's record), so writing a
// record is eight 16-byte copies rather than 32 scalar ones (a third of the front end's time).
struct SetupLanes {
    static constexpr int n = SetupBatch::k_capacity;
    static constexpr int k_units = static_cast<int>(sizeof(TriangleSetup) / 16);
    struct alignas(16) Unit {
        std::uint32_t word[4];
    };
    Unit unit[k_units][n];
    float floor[n];                      // lowest_depth of triangle i's record, when `floors`
    // The tile (FrontEndParams: tile_size pixels square, tiles_x a row) that holds all of triangle
    // i's bounds, or -1 when they reach two or more: found in lanes by the triangles' kernels, for the
    // emitter (the segments' kernel leaves it unset).
    std::int32_t tile[n];
    std::uint32_t keep = 0, culled = 0;  // bit i: triangle i
    bool floors = true;                  // in: whether to set floor
    // The inclusive pixel bounds of triangle i (unit 3: min_x, min_y, max_x, max_y).
    const std::int32_t* bounds(int i) const { return reinterpret_cast<const std::int32_t*>(unit[3][i].word); }
};
// Runs the kernel of the selected ISA on the batch. False when the batch must be set up one by one
// instead (setup_one_by_one): the scalar ISA is selected, or a coordinate is too large to be exact.
bool setup_lanes(const SetupBatch& batch, const FrontEndParams& params, SetupLanes& lanes);
// The record of batch triangle i (a bit of lanes.keep), as setup_triangle writes it.
// (memcpy, not stores through a Unit*: the record is a TriangleSetup, and its bytes are copied.)
inline void write_record(const SetupLanes& lanes, int i, TriangleSetup& t) {
    auto* to = reinterpret_cast<unsigned char*>(&t);
    for (int g = 0; g < SetupLanes::k_units; ++g) std::memcpy(to + 16 * g, lanes.unit[g][i].word, 16);
}
// setup_triangle on each triangle of the batch, the survivors written to out[0, written).
BatchSetupCounts setup_one_by_one(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out);

}  // namespace facet::detail
