// facet internals: the front end of a draw call, compiled once (not per shader).
// In: ClipVertices from the vertex stage and the draw's indices. Per triangle: assemble, reject
// invalid, clip in homogeneous space, project (divide by w, keeping 1/w), snap to fixed point,
// cull, set up edge functions and attribute planes, and bin into screen tiles.
// Out: one FrontEndChunk per contiguous range of triangles; their order is submission order.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "facet/api.hpp"
#include "facet/detail/frame.hpp"

FACET_API_BEGIN
namespace facet::detail {

struct FrontEndParams {
    DrawState state;
    PixelRect scissor;            // viewport clamped to the target
    float vp_x, vp_y, vp_w, vp_h;  // the viewport, in pixels
    int tile_size;
    int tiles_x, tiles_y;
};

// A tile's set-up records in submission order. A record is stored in the bin of every tile it
// reaches (most triangles reach one), so a tile reads its triangles from one array, front to back,
// where the hardware prefetcher follows, rather than by index from anywhere in the chunk.
using TileBin = std::vector<TriangleSetup, UninitialisedAllocator<TriangleSetup>>;

struct FrontEndChunk {
    std::vector<TileBin> bins;  // per tile, row-major
    ClipVertices extras;        // vertices made by clipping
    // Only for a draw with render passes (DrawPasses), else left empty: beside each record of
    // bins[tile], the index of the triangle of the draw it came from (primitives[tile][k] for
    // bins[tile][k]: a side array, so that records stay 128 bytes and draws without passes pay
    // nothing), and the pass varyings of the clip-made vertices (at the indices of `extras`).
    std::vector<std::vector<std::uint32_t>> primitives;
    ClipVertices pass_extras;
    DrawStats stats;
    // `pass_stride`: the pass varyings per vertex of a draw with render passes, or -1 without.
    void reset(std::size_t tile_count, int stride, int pass_stride = -1);
};

// With `pass_vertices` (the pass vertex stage's output, for a draw with render passes) the chunk's
// primitives and pass_extras are filled too.
void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first_triangle,
                   std::size_t end_triangle, const FrontEndParams& params, FrontEndChunk& out,
                   const ClipVertices* pass_vertices = nullptr);

}  // namespace facet::detail
FACET_API_END
