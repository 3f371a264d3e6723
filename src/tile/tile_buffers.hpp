// facet tile pass: one worker's buffers for the tile it draws in the visible-only order (TileBuffers).
// In: the tile's depth from the target (or the clear values), the triangles the depth pass lists, and
// their vertices' varyings. Out: the VisibleTile the shading pass reads, and the tile's depth and
// colour written back to the target when it is done. The depth pass itself is depth_pass.hpp's; the
// shading pass, the shader's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "facet/detail/front_end.hpp"
#include "facet/detail/visible_tile.hpp"
#include "tile/deferred_fills.hpp"
#include "tile/passes.hpp"

namespace facet::detail {

// Where a batch's triangles find their vertices' varyings: the vertex stage's output, and the clip
// extras of the triangle's chunk.
struct VaryingsSource {
    const ClipVertices& vertices;
    const ClipVertices& extras;
    void find(const TriangleSetup& t, const float* (&var)[3]) const {
        for (int k = 0; k < 3; ++k) var[k] = varyings_of(t.vertex[k], vertices, extras);
    }
};

// A tile's triangles that are visible somewhere, in submission order, which of them is visible at
// each pixel, and the tile's depth (and colour, when the draw clears it) while it is drawn.
struct TileBuffers {
    static constexpr std::uint32_t k_none = VisibleTile::k_no_owner;
    // The triangles that passed the depth test at some pixel of the tile when they were drawn (their
    // index here is their id); the others cannot own a pixel, so they are not listed and their
    // varyings are never copied.
    std::vector<const TriangleSetup*> triangles;
    // The shading records (write_shading_record) of the listed triangles from the first that owns a
    // pixel when the depth pass ends, at their ids, `stride` floats apart, so the shading pass reads
    // them from here, not from scattered vertices. The slots before it (triangles that later ones hid
    // everywhere) are neither written nor read. Uninitialised when it grows (a zero-filling resize
    // cost 17 M instructions per bunny frame).
    std::vector<float, UninitialisedAllocator<float>> records;
    // Where each bin's listed triangles end and where their clip-made vertices are (the bin's chunk's
    // extras), in the order the depth pass took the bins.
    struct BinRun {
        std::uint32_t end;
        const ClipVertices* extras;
    };
    std::vector<BinRun> runs;
    int stride = 0;
    int varyings = 0;
    // Rows of owner and depth: three more than the largest tile, never inside a triangle, so that the
    // depth pass, which draws rows in groups of two (four for narrow rectangles), can load and store
    // back unchanged the rows of a group that lie past the tile (their values are never read
    // otherwise) instead of testing for them.
    static constexpr int k_rows = k_max_tile_size + 3;
    // Owner ids per pixel, row-major, VisibleTile::k_row apart, or k_none where no triangle passed the
    // depth test (set for the whole tile by begin(), so the depth pass need not track which pixels it
    // touched first).
    alignas(64) std::uint32_t owner[k_rows * k_max_tile_size];
    // The tile's depth buffer during the depth pass, laid out like owner: loaded by begin(), stored
    // back by end(). Rows that start on a cache line and are 64 wide whatever the tile let the SIMD
    // kernel load and store aligned whole vectors: no split cache lines, no tile-edge special case,
    // and a load of a vector the previous triangle stored is forwarded from the store whole.
    alignas(64) float depth[k_rows * k_max_tile_size];
    // The tile's colour while it is drawn, when the draw clears it (DrawState::clear): the shading
    // pass writes its covered pixels (colour_view), and store_colour() writes the finished tile to
    // the target in whole cache lines, streamed past the caches, with the clear colour where no
    // triangle is visible: the tile is never filled first, the target's old bytes are never read,
    // and each of its lines is written once. (The other pixels hold whatever the last tile left.)
    alignas(64) Rgba8 colour[k_max_tile_size * k_max_tile_size];
    Rgba8 clear_colour{};
    bool depth_cleared = false;   // begin() set depth to a clear value: end() must store it
    bool colour_cleared = false;  // begin() set colour to a clear value: store_colour() must store it
    // Per row, the pixels some triangle owns: set by end() from `owner`, once per tile, rather than
    // by the depth pass for every row of every triangle.
    std::uint64_t covered[k_max_tile_size];
    // No pixel's owner id is below it: the lowest owner id (k_none when no pixel has one), or lower
    // (the SIMD kernel also reads the entries past a narrower tile's width, which hold anything, and
    // gives 0 in tiles of few listed triangles, where the search costs more than the records it
    // saves). Set by end() with covered.
    std::uint32_t first_owner = k_none;
    // Empty tiles this worker was handed, written between the blocks of the shading pass.
    DeferredFills fills;
    // A draw with render passes (tile/passes.hpp): each listed triangle's pass record, `pass_stride`
    // floats apart (pass_record_floats).
    std::vector<float, UninitialisedAllocator<float>> pass_records;  // resize() leaves them to write_pass_records
    int pass_stride = 0;
    PassRow pass_row;  // a row of the passes of a tile the draw clears, before it goes to the targets

    static_assert(VisibleTile::k_row == k_max_tile_size, "owner and depth rows are VisibleTile's");

    // Room for `count` triangles with `varyings` each, from `bins` bins, so that drawing a tile of that
    // many allocates nothing.
    void reserve(std::size_t count, int varyings, int pass_varyings = -1, std::size_t bins = 0);  // -1: no render passes
    struct Clear {
        Rgba8 colour;
        float depth;
    };
    // Starts a tile: its depth copied from the target, or, when the draw clears it, its depth and
    // colour set to the clear values (then the target's tile is neither read nor cleared first).
    void begin(PixelRect tile, int varyings, TargetView target, const Clear* clear = nullptr);
    // Starts a tile of the one-pass order with render passes: no owner yet, no triangle listed. (Then
    // each triangle drawn is listed, and owns the pixels whose depth it writes.)
    void begin_owners(PixelRect tile);
    // The depth pass has listed the triangles of a bin of the chunk whose clip-made vertices are
    // `extras`: the next bin's start from here.
    void end_bin(const ClipVertices& extras) {
        runs.push_back({static_cast<std::uint32_t>(triangles.size()), &extras});
    }
    // Ends the depth pass: finds the covered pixels, and writes the tile's depth back to the target
    // when it changed (cleared by begin() or written by the depth pass, depth_write) and the draw
    // stores its depth (store_depth). Without `fence`, the caller fences the streamed rows
    // (fence_streams) before the tile is reported done.
    void end(PixelRect tile, TargetView target, bool depth_write, bool store_depth = true, bool fence = true);
    // After end(): the shading records of the listed triangles from first_owner on, their varyings in
    // `vertices` or in their bin's extras (end_bin).
    void write_shading_records(const ClipVertices& vertices);
    // What the shading pass reads (valid until the next begin()).
    VisibleTile visible(PixelRect tile) {
        return {tile, owner, covered, static_cast<std::uint32_t>(triangles.size()), triangles.data(), records.data(),
                stride, &fills};
    }
    // Where the shading pass writes: the tile's own colour when begin() cleared it, else the target.
    TargetView colour_view(PixelRect tile, TargetView target) {
        return colour_cleared ? TargetView{colour, nullptr, k_max_tile_size, tile.x0, tile.y0} : target;
    }
    // After the shading pass: the tile's own colour, if it has one, to the target, the clear colour
    // where no pixel was covered; `fence` as in end().
    void store_colour(PixelRect tile, TargetView target, bool fence = true) const;
};

}  // namespace facet::detail
