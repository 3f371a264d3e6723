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
    // The tiles are drawn by more than one thread: a bin's records are read by whichever thread
    // draws its tile, so the front end writes them past the caches (Emitter::bin_across_tiles).
    bool shared_bins = false;
};

// A tile's set-up records in submission order. A record is stored in the bin of every tile it
// reaches (most triangles reach one), so a tile reads its triangles from one array, front to back,
// where the hardware prefetcher follows, rather than by index from anywhere in the chunk.
using TileBin = std::vector<TriangleSetup, UninitialisedAllocator<TriangleSetup>>;

// The tile pass hands the depth pass a bin this many records (32 KB) at a time; the front end keeps
// the lowest depth of each such piece (FrontEndChunk::depth_floors).
constexpr std::size_t k_bin_piece = 256;

struct FrontEndChunk {
    std::vector<TileBin> bins;  // per tile, row-major
    ClipVertices extras;        // vertices made by clipping
    // Only for a draw with render passes (DrawPasses), else left empty: beside each record of
    // bins[tile], the index of the triangle of the draw it came from (primitives[tile][k] for
    // bins[tile][k]: a side array, so that records stay 128 bytes and draws without passes pay
    // nothing), and the pass varyings of the clip-made vertices (at the indices of `extras`).
    std::vector<std::vector<std::uint32_t>> primitives;
    ClipVertices pass_extras;
    // Per tile, per piece of k_bin_piece records of bins[tile], the lowest depth any of them gives a
    // pixel (lowest_depth, src/setup/setup.hpp), so that the tile pass can pass over a piece that lies
    // behind every pixel of the tile without reading it: the far side of a closed mesh drawn after
    // its near side. Only for a depth test less or lequal (floors_for) and chunks of 64 triangles a
    // tile or more (Emitter::wants_floors); else each is left empty.
    std::vector<std::vector<float>> depth_floors;
    DrawStats stats;
    // `pass_stride`: the pass varyings per vertex of a draw with render passes, or -1 without.
    void reset(std::size_t tile_count, int stride, int pass_stride = -1);
};

// Whether the front end keeps depth_floors for a draw with this depth test: a piece lying wholly at
// or behind the tile's depth fails these tests everywhere.
inline bool floors_for(DepthTest test) { return test == DepthTest::less || test == DepthTest::lequal; }

// With `pass_vertices` (the pass vertex stage's output, for a draw with render passes) the chunk's
// primitives and pass_extras are filled too.
void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first_triangle,
                   std::size_t end_triangle, const FrontEndParams& params, FrontEndChunk& out,
                   const ClipVertices* pass_vertices = nullptr);

}  // namespace facet::detail
FACET_API_END
