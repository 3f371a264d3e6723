// facet internals: the types handed from stage to stage inside one draw call.
//   vertex stage  -> ClipVertices   (pos_clip + varyings per vertex)
//   front end     -> TriangleSetup  (assembled, clipped, culled, projected, snapped, set up) + bins
//   coverage      -> TileCoverage   (one bit per pixel of a tile; the one-pass order)
//   depth pass    -> VisibleTile    (which triangle owns each pixel of a tile: visible_tile.hpp)
//   fragment stage (fragment.hpp)   -> Framebuffer pixels
// Shared by the compiled stages in src/ and the shader-templated ones in the headers.
#pragma once

#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "facet/api.hpp"
#include "facet/image.hpp"
#include "facet/math/vec.hpp"
#include "facet/pipeline.hpp"

FACET_API_BEGIN
namespace facet::detail {

// 8 sub-pixel bits: vertices snap to 1/256 pixel, as in llvmpipe and D3D. Together with
// k_max_target_size and the guard band (src/geometry/project.hpp) this keeps coordinates within 2^22
// and edge steps in 32 bits.
constexpr int k_subpixel_bits = 8;
constexpr int k_subpixel_one = 1 << k_subpixel_bits;

// Tiles are square; a row of coverage is one 64-bit word, so at most 64 pixels wide.
constexpr int k_max_tile_size = 64;

// A vertex after projection: snapped screen position and what the attribute planes need.
struct ScreenVertex {
    std::int32_t x, y;  // fixed point, k_subpixel_bits fractional bits
    float z, q;         // window depth in [0, 1] and 1/w
};

// Outcode bit for a vertex with a NaN or infinite coordinate (the clip planes use bits 0-6).
constexpr std::uint8_t k_outcode_invalid = 0x80;

// A vector of UninitialisedAllocator (facet/image.hpp): resize() writes nothing.
template <class T>
using UninitialisedVector = std::vector<T, UninitialisedAllocator<T>>;

// Vertex stage output, structure of arrays: pos[i] and varyings[i * stride .. + stride).
// The projection pass adds outcode[i] and, for vertices inside every clip plane, screen[i]:
// each vertex is projected once, not once per triangle that uses it.
struct ClipVertices {
    UninitialisedVector<Vec4> pos;  // written by the stages, never cleared first (but see recompute)
    UninitialisedVector<float> varyings;
    UninitialisedVector<std::uint8_t> outcode;
    UninitialisedVector<ScreenVertex> screen;
    int stride = 0;
    // n vertices of stride_ varyings, not written here (the vertex stage and the projection write
    // every one). Arrays that grow are reserved first in 2 MiB pages where the
    // system grants them (src/exec/fresh_pages.hpp): the tiles read a line's or a point's varyings
    // from anywhere in the draw, one translation each in 4 KiB pages.
    void resize(std::size_t n, int stride_);
    const float* varyings_of(std::uint32_t i) const { return varyings.data() + static_cast<std::size_t>(i) * stride; }
    // Set by a compiled vertex stage, which projects its positions from a buffer of its own and leaves
    // pos unwritten (8 MB a frame for 500k vertices, read only by clipping): recompute(source, i) is
    // then vertex i's clip position, the same bits. Null: pos holds them.
    Vec4 (*recompute)(const void* source, std::uint32_t i) = nullptr;
    const void* source = nullptr;
    // Vertex i's clip position, for the few triangles and segments that need clipping.
    Vec4 clip_position(std::uint32_t i) const { return recompute ? recompute(source, i) : pos[i]; }
};

// A triangle ready for rasterization. Edge i is e(ix, iy) = e0 + a*(ix - min_x) + b*(iy - min_y) in
// pixel units, where (ix, iy) is a pixel index and its centre is (ix + 0.5, iy + 0.5); the pixel is
// covered when all three are >= 0 (the top-left rule is folded into e0). e0, the value at the
// bounds' corner, is given rather than the value at pixel (0, 0): over bounds within one tile every
// value then fits in 32 bits, and a tile's kernel can start from e0 as it is. Attribute planes are
// evaluated relative to (x0, y0), the first vertex, so precision does not depend on where the
// triangle is on screen. Two cache lines, aligned: the tiles read a record as two whole lines, never three.
struct alignas(64) TriangleSetup {
    std::int32_t a[3], b[3];         // |a|, |b| < 2^24: differences of snapped coordinates
    std::int64_t e0[3];              // each edge at pixel (min_x, min_y)
    int min_x, min_y, max_x, max_y;  // inclusive pixel bounds, already clamped to the scissor
    float x0, y0;
    float z0, dzdx, dzdy;            // window depth, linear in screen space
    float q0, dqdx, dqdy;            // q = 1/w, linear in screen space
    float dl1dx, dl1dy;              // barycentric b1 times q (0 at (x0, y0): b1 is 0 at vertex 0)
    float dl2dx, dl2dy;              // barycentric b2 times q (likewise)
    std::uint32_t vertex[3];         // varyings: ClipVertices index, or k_clipped_bit | index into the clip extras
    bool front_facing;
    bool small_edges;                // edges_fit_32_bits: set by setup, so pass one need not test it per tile
    bool segment;                    // a line segment's quad (raster/segment.hpp): a, b and e0 hold four edges
    std::uint8_t line_aa;            // an anti-aliased segment (line_aa.hpp): bit k, its coverage fades to edge k
};

static_assert(sizeof(TriangleSetup) == 128);

// Edge k of t at pixel (ix, iy): exact (|a|, |b| < 2^24 and pixel indices below 2^15 keep every
// product and sum far inside 64 bits).
inline std::int64_t edge_at(const TriangleSetup& t, int k, std::int64_t ix, std::int64_t iy) {
    return t.e0[k] + t.a[k] * (ix - t.min_x) + t.b[k] * (iy - t.min_y);
}

// True when every edge of t fits in 32 bits over its whole bounds: |e0| < 2^30 plus at most
// (width + height) < 2^14 steps (k_max_target_size) of at most 2^15 is below 2^31. Most triangles
// are small; the others reach far outside the target (their bounds are clamped to it, so the size of
// the bounds alone does not say it). Needs t's edges.
inline bool edges_fit_32_bits(const TriangleSetup& t) {
    static_assert(2 * 8192 <= (1 << 14), "k_max_target_size (facet/image.hpp)");
    bool small = true;
    for (int k = 0; k < 3; ++k)
        small &= (t.a[k] >= -(1 << 15)) & (t.a[k] <= (1 << 15)) & (t.b[k] >= -(1 << 15)) & (t.b[k] <= (1 << 15)) &
                 (t.e0[k] > -(1 << 30)) & (t.e0[k] < (1 << 30));
    return small;
}

constexpr std::uint32_t k_clipped_bit = 0x80000000u;

// The varyings of vertex `ref` of a triangle (TriangleSetup::vertex): the vertex stage's, or for a
// vertex made by clipping, those in the clip extras of the triangle's chunk.
inline const float* varyings_of(std::uint32_t ref, const ClipVertices& vertices, const ClipVertices& extras) {
    return (ref & k_clipped_bit) ? extras.varyings_of(ref & ~k_clipped_bit) : vertices.varyings_of(ref);
}

// GCC 12 removes __builtin_prefetch whose address comes from loads it can see through (the function
// holding it counts as side-effect free and its call disappears); an asm statement stays.
inline void prefetch(const void* p) {
#if defined(__x86_64__) || defined(__i386__)
    asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
    __builtin_prefetch(p);
#endif
}
// Both cache lines of the record at p, fetched to be read.
inline void prefetch_record(const TriangleSetup* p) {
    prefetch(p);
    prefetch(reinterpret_cast<const char*>(p) + 64);
}
// Both cache lines of the record at p, fetched to be written.
inline void prefetch_for_write(const TriangleSetup* p) {
#if defined(__x86_64__) || defined(__i386__)
    const char* line = reinterpret_cast<const char*>(p);
    asm volatile("prefetchw %0" : : "m"(*line));
    asm volatile("prefetchw %0" : : "m"(*(line + 64)));
#else
    __builtin_prefetch(p, 1);
    __builtin_prefetch(reinterpret_cast<const char*>(p) + 64, 1);
#endif
}

// One bit per pixel: rows[r] bit i is pixel (tile_x + i, tile_y + r).
struct TileCoverage {
    std::uint64_t rows[k_max_tile_size];
    int first_row, last_row;  // rows outside [first_row, last_row] are empty (last < first: nothing)
};

struct PixelRect {
    int x0, y0, x1, y1;  // half-open: [x0, x1) x [y0, y1)
};

// Where a stage writes pixels: the framebuffer (origin 0, 0), or a tile's own buffer whose first
// pixel is (x0, y0) of the target.
struct TargetView {
    Rgba8* colour;
    float* depth;
    int stride;  // pixels per row
    int x0 = 0, y0 = 0;
    // Index of pixel (x, y), x >= x0 and y >= y0, in colour and depth.
    std::size_t at(int x, int y) const {
        return static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(x - x0);
    }
};

// Coverage of one triangle within one tile (clamped to the triangle's bounds). Exact: integer
// edge functions, top-left rule. Returns false when no pixel is covered.
bool rasterize_tile(const TriangleSetup& tri, PixelRect tile, TileCoverage& out);
// The same result by the scalar row-span algorithm: the specification the SIMD path is tested against.
bool rasterize_tile_reference(const TriangleSetup& tri, PixelRect tile, TileCoverage& out);

}  // namespace facet::detail
FACET_API_END
