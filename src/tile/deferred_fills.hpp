// facet tile pass: the clears of the tiles no triangle reaches, deferred (DeferredFills). In: the
// empty tiles of a clearing draw that a worker is handed. Out: their rows of clear colour and depth,
// written by streaming stores a few at a time in the moments a shading kernel leaves the stores idle
// (VisibleTile::idle, stream_fill-inl.h), the rest after the tiles (drain_fills). Does not decide
// which tiles are deferred (tile_pass.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "facet/detail/frame.hpp"

namespace facet::detail {

// Tiles of the target that the draw clears and no triangle reaches, to be filled with the clear
// colour and depth by streaming stores a row at a time, between the tile kernels' own work, instead
// of all at once. A core writes memory past its caches at a limited rate (about 40 GB/s here), and
// a run of such fills leaves it waiting for every line: at 1920x1080 the empty tiles around a model
// are 13 MB a frame. Written a few rows at a time between the blocks of the compiled shading pass
// (take(), then stream_fill_rows), they cost a fraction of that. One queue per pool worker (in its
// TileBuffers): the empty tiles a worker is handed join its queue, and what is left when the tiles
// are done is written by drain_fills (all of it for shaders without a compiled pass). Only tiles
// whose every row is whole aligned cache lines are queued; the image does not depend on when they
// are written.
struct DeferredFills {
    struct Tile {
        std::uint32_t* colour;  // the tile's first colour and depth pixels in the target
        std::uint32_t* depth;
        int width, height;
    };
    // One row to write: `width` words of value `word` from `to`, 64-byte aligned, width a multiple of 16.
    struct Row {
        std::uint32_t* to;
        int width;
        std::uint32_t word;
    };
    std::vector<Tile> tiles;
    std::size_t next = 0;  // tiles[next] is being written, row `row` of colour then of depth
    int row = 0;
    int stride = 0;        // the target's row, in pixels
    std::uint32_t colour = 0, depth = 0;  // the clear values' bits
    int layers = 2;         // rows per tile row: colour and depth, or colour alone (no depth store)
    bool streamed = false;  // rows were taken since the last fence

    // Empties the queue (it must have been drained) for a draw that clears to `c` and `z` (colour
    // alone without `with_depth`), with room for all `tile_count` tiles of the target: queueing them
    // allocates nothing.
    void start(TargetView target, Rgba8 c, float z, bool with_depth, std::size_t tile_count) {
        tiles.clear();
        tiles.reserve(tile_count);
        next = 0, row = 0;
        stride = target.stride;
        layers = with_depth ? 2 : 1;
        std::memcpy(&colour, &c, sizeof(colour));
        std::memcpy(&depth, &z, sizeof(depth));
    }
    // Whether `tile` of the target can be queued: every row whole aligned cache lines.
    static bool fits(TargetView target, PixelRect tile) {
        constexpr int k_line = 64 / sizeof(std::uint32_t);
        return (tile.x1 - tile.x0) % k_line == 0 && target.stride % k_line == 0 &&
               reinterpret_cast<std::uintptr_t>(target.colour + target.at(tile.x0, tile.y0)) % 64 == 0 &&
               reinterpret_cast<std::uintptr_t>(target.depth + target.at(tile.x0, tile.y0)) % 64 == 0;
    }
    void add(TargetView target, PixelRect tile) {
        tiles.push_back({reinterpret_cast<std::uint32_t*>(target.colour + target.at(tile.x0, tile.y0)),
                         reinterpret_cast<std::uint32_t*>(target.depth + target.at(tile.x0, tile.y0)),
                         tile.x1 - tile.x0, tile.y1 - tile.y0});
    }
    // (By pointers: size() divides by the 24 bytes of a Tile, and take() runs before every shaded block.)
    bool pending() const { return tiles.begin() + static_cast<std::ptrdiff_t>(next) < tiles.end(); }
    // The next row of the queue (a tile's colour rows, then its depth rows), if any, for the caller
    // to write with streaming stores (stream_fill_row).
    [[gnu::always_inline]] bool take(Row& out) {
        if (!pending()) return false;
        const Tile& t = tiles[next];
        const bool is_colour = row < t.height;
        const int r = is_colour ? row : row - t.height;
        out = {(is_colour ? t.colour : t.depth) + static_cast<std::size_t>(r) * static_cast<std::size_t>(stride),
               t.width, is_colour ? colour : depth};
        streamed = true;
        if (++row == layers * t.height) row = 0, ++next;
        return true;
    }
};
// drain_fills writes all that is left of a queue and ends with a fence when the queue's rows were
// streamed since the last one: streaming stores are weakly ordered, so they are made visible before
// the work that wrote them is reported done (by each worker after its last tile of a batch). SIMD,
// in tile_store_simd.cpp.
void drain_fills(DeferredFills& fills);

}  // namespace facet::detail
