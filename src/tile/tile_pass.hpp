// facet tile pass: the back end of a draw, one batch at a time. In: the front end's bins of
// TriangleSetup records (one FrontEndChunk per range of triangles, in submission order), the
// vertices' varyings and what the draw calls of its shader (TileShading). Every tile is drawn by one
// thread, in the order tile_order gives: cleared when the draw clears (by the tile's own buffers,
// directly, or deferred between other work when no triangle reaches it), then either the depth pass
// of all its triangles followed by the shader's pass over the VisibleTile, or each covered triangle
// shaded in turn (DrawOrder); with render passes, then the passes of its visible pixels
// (tile/passes.hpp). Out: the target's pixels. Compiled once, not per shader; it knows the shader
// only through TileShading's entry points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "facet/detail/draw_order.hpp"
#include "facet/detail/front_end.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/image.hpp"

namespace facet::detail {

struct TileBuffers;
struct PassDraw;

// What the tile pass reads of one batch.
struct TileBatch {
    const FrontEndChunk* chunks;  // in submission order
    std::size_t chunk_count;
    const ClipVertices& vertices;  // the vertex stage's output: varyings of the unclipped vertices
    const FrontEndParams& params;  // tiles and scissor
};

class TilePass {
public:
    explicit TilePass(int workers);  // the pool's workers: one set of tile buffers each
    ~TilePass();

    // Draws every tile of `batch` into `target`, and with `passes` its render passes into their
    // targets. With `clear`, each tile is first cleared to DrawState::clear (params.state.clear), and
    // its passes to their background, the whole tile, inside the viewport or not. Without
    // `store_depth`, the visible-only order leaves the target's depth as it was (DrawState::keep_depth).
    void run(ThreadPool& pool, const TileBatch& batch, Framebuffer& target, const TileShading& shading, bool clear,
             bool store_depth,
             const PassDraw* passes = nullptr);

private:
    // Fills order_ from the bins, and returns the most triangles binned to one tile.
    std::size_t order_tiles(const TileBatch& batch);

    // The order in which the tiles of the current batch are handed out: the tiles with triangles in
    // index order, and the empty ones spread evenly between them, so that every worker's queue of
    // empty tiles to clear (DeferredFills) grows with the work during which it writes them, rather
    // than one worker being handed the rows above a model and another the model. The image does not
    // depend on the order.
    std::vector<std::uint32_t> order_;
    std::vector<std::unique_ptr<TileBuffers>> buffers_;  // one per pool worker
};

}  // namespace facet::detail
