// facet tile pass: the depth pass of the visible-only order, pass one of a tile. In: a tile's bins of
// TriangleSetup records in submission order, and its TileBuffers. Per triangle: coverage within the
// tile, the depth test (and write) at every covered pixel, and the triangle becomes the owner of each
// pixel where it passes; triangles that pass somewhere are listed. Out: the TileBuffers' depth,
// owners and list, then (find_owned_pixels) which pixels have an owner: the VisibleTile. Compiled
// once, not per shader: SIMD kernels in depth_simd.cpp, the scalar specification here. Does not
// shade or write the target.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "facet/detail/fragment.hpp"
#include "tile/tile_buffers.hpp"

namespace facet::detail {

template <DepthTest D>
inline bool depth_passes(float z, float stored) {
    if constexpr (D == DepthTest::less) return z < stored;
    if constexpr (D == DepthTest::lequal) return z <= stored;
    if constexpr (D == DepthTest::equal) return z == stored;
    if constexpr (D == DepthTest::greater) return z > stored;
    if constexpr (D == DepthTest::always) return true;
    return false;
}

// Calls f.template operator()<D>() with the depth test `test` as a template argument (nothing for
// never, which draws nothing: DrawOrder::nothing): where a run-time choice becomes a compile-time one.
template <class F>
void with_depth_test(DepthTest test, F&& f) {
    switch (test) {
        case DepthTest::never: break;
        case DepthTest::less: f.template operator()<DepthTest::less>(); break;
        case DepthTest::lequal: f.template operator()<DepthTest::lequal>(); break;
        case DepthTest::equal: f.template operator()<DepthTest::equal>(); break;
        case DepthTest::greater: f.template operator()<DepthTest::greater>(); break;
        case DepthTest::always: f.template operator()<DepthTest::always>(); break;
    }
}

// Pass one, for one triangle: coverage within the tile, then the depth test (and write) at every
// covered pixel; the triangle becomes the owner (id) of each pixel where it passes.
struct DepthJob {
    const TriangleSetup* setup;
    PixelRect tile;
    TileBuffers* buffers;  // depth and owner are updated; the triangle list is the caller's
    std::uint32_t id;
    DepthTest test;
    bool write;
};

// The depth test of the covered pixels, one pixel at a time. Returns true when some pixel passed.
template <DepthTest D, bool DepthWrite>
bool resolve_depth_reference(const DepthJob& job, const TileCoverage& cov) {
    const TriangleSetup& t = *job.setup;
    bool any = false;
    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = job.tile.y0 + row;
        float* depth_row = job.buffers->depth + row * k_max_tile_size;
        std::uint32_t* owner_row = job.buffers->owner + row * k_max_tile_size;
        while (mask) {
            const int i = std::countr_zero(mask);
            mask &= mask - 1;
            const int x = job.tile.x0 + i;
            const float z = depth_at(t, x, y);
            if (!depth_passes<D>(z, depth_row[i])) continue;
            if constexpr (DepthWrite) depth_row[i] = z;
            owner_row[i] = job.id;
            any = true;
        }
    }
    return any;
}

// The scalar specification of pass one: the reference coverage, then resolve_depth_reference.
template <DepthTest D, bool DepthWrite>
bool resolve_triangle_reference(const DepthJob& job) {
    TileCoverage cov;
    if (!rasterize_tile_reference(*job.setup, job.tile, cov)) return false;
    return resolve_depth_reference<D, DepthWrite>(job, cov);
}

// Pass one for the ISA selected in facet/isa.hpp: a SIMD kernel that computes coverage and depth in
// one sweep (depth_simd.cpp), or resolve_triangle_reference when "scalar" is selected. Same bytes
// either way. Returns true when the triangle passed the depth test at some pixel, i.e. owns pixels
// now; one that does not can never own any in this tile.
bool resolve_triangle(const DepthJob& job);
// The function resolve_triangle calls for this depth test and write flag with the ISA selected now:
// chosen once per draw, it saves the dispatch per triangle.
using ResolveTriangleKernel = bool (*)(const DepthJob&);
ResolveTriangleKernel resolve_triangle_kernel(DepthTest test, bool write);
// Pass one over a tile's bin, `count` records in submission order: each triangle is resolved as by
// resolve_triangle with the id buffers.triangles.size(), and appended to buffers.triangles when it
// passed somewhere. One call per bin, not per triangle: the kernel keeps the tile's constants in
// registers and fetches the records ahead itself.
using ResolveBinKernel = void (*)(const TriangleSetup* records, std::size_t count, PixelRect tile,
                                  TileBuffers& buffers);
// With `large`, for the less and lequal tests that write depth, a kernel for draws of large triangles:
// it does not draw the rows of a large rectangle's strips where nothing is inside. The same bytes
// either way. Small triangles keep the other kernel (with the test for large rectangles in it, never
// true for them, homer's frame was 2% slower: docs/BENCHMARKS.md, session 14).
ResolveBinKernel resolve_bin_kernel(DepthTest test, bool write, bool large = false);
// A draw whose fullest tile has at most this many triangles has large ones (nefertiti: 562 triangles
// at 1920x1080): resolve_bin_kernel's `large`.
constexpr std::size_t k_large_triangles_per_tile = 128;

// Sets TileBuffers::covered and first_owner from the owners, with the ISA selected in facet/isa.hpp
// (a SIMD kernel in depth_simd.cpp, or find_owned_pixels_reference).
void find_owned_pixels(TileBuffers& buffers, PixelRect tile);

// The largest depth of the tile's pixels in the depth pass, with the ISA selected in facet/isa.hpp (a
// SIMD kernel in depth_simd.cpp, or tile_depth_ceiling_reference). No depth test passes against a NaN:
// a kernel may leave NaN out or return it (then nothing is above it). -infinity for an empty tile.
float tile_depth_ceiling(const TileBuffers& buffers, PixelRect tile);

// The scalar specification of tile_depth_ceiling: NaN left out.
inline float tile_depth_ceiling_reference(const TileBuffers& buffers, PixelRect tile) {
    float ceiling = -std::numeric_limits<float>::infinity();
    for (int row = 0; row < tile.y1 - tile.y0; ++row)
        for (int i = 0; i < tile.x1 - tile.x0; ++i) {
            const float d = buffers.depth[row * k_max_tile_size + i];
            ceiling = d > ceiling ? d : ceiling;
        }
    return ceiling;
}

// The scalar specification of find_owned_pixels.
inline void find_owned_pixels_reference(TileBuffers& buffers, PixelRect tile) {
    buffers.first_owner = TileBuffers::k_none;
    for (int row = 0; row < tile.y1 - tile.y0; ++row) {
        std::uint64_t bits = 0;
        for (int i = 0; i < tile.x1 - tile.x0; ++i) {
            const std::uint32_t owner = buffers.owner[row * k_max_tile_size + i];
            bits |= std::uint64_t{owner != TileBuffers::k_none} << i;
            buffers.first_owner = std::min(buffers.first_owner, owner);
        }
        buffers.covered[row] = bits;
    }
}

}  // namespace facet::detail
