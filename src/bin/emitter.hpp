// facet bin: the Emitter, which sets up the front end's triangles (the SIMD batch or one by one) and
// bins their records into screen tiles in submission order. In: projected, snapped triangles (from
// assembled triangles, clipped polygons, or the quads of points and lines), points' pixel rectangles
// and segments' records. Out: the chunk's bins.
// Does not assemble, clip or project.
#pragma once

#include <algorithm>
#include <bit>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "facet/detail/front_end.hpp"
#include "raster/segment.hpp"
#include "setup/setup.hpp"

namespace facet::detail {

// True when the edge function is negative over the whole rectangle (no pixel of it is inside).
inline bool edge_rejects(const TriangleSetup& t, int e, const PixelRect& r) {
    // The largest value of a*x + b*y + c over the rectangle is at the corner its gradient points to.
    const std::int64_t x = t.a[e] > 0 ? r.x1 - 1 : r.x0;
    const std::int64_t y = t.b[e] > 0 ? r.y1 - 1 : r.y0;
    return edge_at(t, e, x, y) < 0;
}

// The number of bits set in a batch's lane mask. std::popcount compiles to a call into libgcc here
// (this code is built for x86-64's baseline, without POPCNT): 1% of a 9,856-triangle frame.
inline int count_lanes(std::uint32_t m) {
    m = m - ((m >> 1) & 0x55555555u);
    m = (m & 0x33333333u) + ((m >> 2) & 0x33333333u);
    return static_cast<int>((((m + (m >> 4)) & 0x0f0f0f0fu) * 0x01010101u) >> 24);
}

// Sets up each triangle and stores its record in the bin of every tile it reaches. Unclipped
// triangles are collected into a batch set up together by the SIMD kernel; the batch is flushed
// before any clipped triangle and at the end, so every bin keeps submission order. A record that
// goes to one tile (most) is written straight into its bin; the others are set up in a small
// scratch array (it stays in L1) and copied into each bin. With Primitives (a draw with render
// passes), the index of each record's triangle goes beside it, into the chunk's primitives.
template <bool Primitives>
class Emitter {
    static constexpr int k_record_write_distance = 24;

public:
    // `primitives`: how many the chunk holds, for the bins' first allocations (first_bin_capacity).
    Emitter(const FrontEndParams& p, FrontEndChunk& out, std::size_t primitives)
        : p_(p), out_(out), first_capacity_(first_bin_capacity(primitives, p)), floors_(wants_floors(primitives, p)) {
        lanes_.floors = floors_;
    }

    // Triangle `triangle` of the draw, vertices i0, i1, i2 of `screen`, each inside all clip planes
    // (most triangles): set up later with its batch. The count is stored, not incremented in place:
    // the vertices' stores could change it, so `++count` read it back from memory.
    void add_unclipped(const ScreenVertex* screen, std::uint32_t i0, std::uint32_t i1, std::uint32_t i2,
                       std::uint32_t triangle) {
        const int i = batch_.count;
        batch_.v[0][i] = screen[i0], batch_.v[1][i] = screen[i1], batch_.v[2][i] = screen[i2];
        batch_.ref[0][i] = i0, batch_.ref[1][i] = i1, batch_.ref[2][i] = i2;
        if constexpr (Primitives) primitive_[i] = triangle;
        batch_.count = i + 1;
        if (i + 1 == SetupBatch::k_capacity) flush();
    }

    // A projected, snapped triangle made from primitive `primitive` (a quad's half of a point or a line
    // segment), its vertices' varyings named by `ref`: set up later with its batch, like the unclipped
    // triangles. (The SIMD set-up takes the same coordinate range as clip-made vertices; larger ones
    // make the whole batch go one by one, the same bytes.)
    void add(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], std::uint32_t primitive) {
        const int i = batch_.count;
        for (int k = 0; k < 3; ++k) {
            batch_.v[k][i] = v[k];
            batch_.ref[k][i] = ref[k];
        }
        if constexpr (Primitives) primitive_[i] = primitive;
        if (++batch_.count == SetupBatch::k_capacity) flush();
    }

    // The pixels of `r` (inside the scissor, not empty) at point c's depth and 1/w, with vertex `ref`'s
    // varyings: a point's square, or a run of a round point's rows. One record and no set-up: its
    // edges are 0 everywhere (so it covers exactly its bounds) and its planes are flat, which gives
    // every pixel the bytes the quad's two triangles gave it (their planes were flat too: the same
    // depth, 1/w and varyings at every corner), at half the records. The pending batch goes first.
    void add_rect(const PixelRect& r, const ScreenVertex& c, std::uint32_t ref, std::uint32_t primitive) {
        flush();
        const BinGrid grid = grid_of();
        const int max_x = r.x1 - 1, max_y = r.y1 - 1;
        ++set_up_;
        if (grid.one_tile(r.x0, max_x, r.y0, max_y)) {
            write_rect(r, c, ref, scratch_[0]);
            const std::size_t tile = grid.tile_of_pixel(r.x0, r.y0);
            stream_copy(scratch_[0], slot<false>(grid, tile, primitive));
            note_floor(grid, tile, scratch_[0]);
            streamed_ = true;
            return;
        }
        write_rect(r, c, ref, scratch_[0]);
        bin_across_tiles(scratch_[0], grid.tiles_of(r.x0, max_x, r.y0, max_y), primitive);
    }

    // A line segment's record (raster/segment.hpp) of primitive `primitive`, made by segment_record.
    // The pending batch goes first.
    void add_segment(const TriangleSetup& t, std::uint32_t primitive) {
        flush();
        ++set_up_;
        bin(t, primitive);
    }
    // The segments of a batch made by setup_segment_lanes whose bits are set in `keep` (a subset of
    // lanes.keep), in order, segment i of primitive primitive[i]; likewise. Records that go to one
    // tile are written past the caches (streaming stores): nothing reads them before the tiles, after
    // the whole front end, and a large draw's are many times the cache (1M segments: 128 MB), where
    // an ordinary store first reads the line it writes, a third of the records' memory traffic.
    void add_segments(const SetupLanes& lanes, std::uint32_t keep, const std::uint32_t* primitive) {
        flush();
        set_up_ += static_cast<std::uint64_t>(std::popcount(keep));
        const BinGrid grid = grid_of();
        for (; keep != 0; keep &= keep - 1) {
            const int i = std::countr_zero(keep);
            bin_lanes_record<true>(grid, lanes, i, primitive[i]);
        }
        streamed_ = true;
    }

    // A triangle made by clipping triangle `triangle`: the pending batch goes first, so records keep
    // submission order.
    void emit(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], std::uint32_t triangle) {
        flush();
        set_up_and_bin(v, ref, triangle);
    }

    void finish() {
        flush();
        // Streaming stores are weakly ordered: the fence puts them before the hand-off to the tiles.
#if defined(__SSE2__)
        if (streamed_) _mm_sfence();
#endif
        out_.stats.triangles_rasterized += set_up_;
        out_.stats.triangles_culled += culled_;
    }

private:
    // Sets up the pending batch in one go (SIMD) and bins the survivors in batch order.
    void flush() {
        if (batch_.count == 0) return;
        if (!setup_lanes(batch_, p_, lanes_)) {  // one by one, as setup_one_by_one does
            for (int i = 0; i < batch_.count; ++i) {
                const ScreenVertex v[3] = {batch_.v[0][i], batch_.v[1][i], batch_.v[2][i]};
                const std::uint32_t ref[3] = {batch_.ref[0][i], batch_.ref[1][i], batch_.ref[2][i]};
                set_up_and_bin(v, ref, primitive_[i]);
            }
            batch_.count = 0;
            return;
        }
        culled_ += static_cast<std::uint64_t>(count_lanes(lanes_.culled));
        set_up_ += static_cast<std::uint64_t>(count_lanes(lanes_.keep));
        // A local copy: the record copies below may write any byte, so what a member holds would be
        // read again from memory for every triangle.
        const BinGrid grid = grid_of();
        // With shared bins, streaming stores as in bin_across_tiles: an ordinary store would first
        // fetch its line from the core whose tile pass read it last frame (the 1M sphere at 2 threads:
        // a tenth of its frame). One thread keeps ordinary stores: it owns its lines already, and its
        // streaming stores write slower (docs/BENCHMARKS.md, session 13).
        if (p_.shared_bins) {
            bin_lanes_records<true>(grid);
            streamed_ = true;
        } else {
            bin_lanes_records<false>(grid);
        }
        batch_.count = 0;
    }

    // A new record at the end of `tile`'s bin, to be written by the caller. The bin's lines a few
    // records on are owned before they are written: a bin is a stream the hardware has not learnt,
    // and a store that misses waits for its line (measured 6% of a 1M-triangle frame). Past the
    // allocation, a prefetch does nothing. 24 records (3 KB) on: since records are written as 16-byte
    // copies, 8 was too close (the 1M-triangle sphere's front end 19.8 -> 17.2 ms; 16 to 64 measured
    // the same).
    struct BinGrid;
    template <bool Prefetch = true>
    [[gnu::always_inline]] static TriangleSetup& slot(const BinGrid& grid, std::size_t tile, std::uint32_t primitive) {
        TriangleSetup& t = grid.bin(tile).emplace_back();
        if constexpr (Primitives) grid.primitives[tile].push_back(primitive);
        if constexpr (Prefetch) prefetch_for_write(&t + k_record_write_distance);
        return t;
    }

    // write_record by streaming stores (whole 16-byte units of an aligned record: whole lines).
    static void stream_record(const SetupLanes& lanes, int i, TriangleSetup& t) {
#if defined(__SSE2__)
        auto* to = reinterpret_cast<__m128i*>(&t);
        for (int g = 0; g < SetupLanes::k_units; ++g)
            _mm_stream_si128(to + g, _mm_load_si128(reinterpret_cast<const __m128i*>(lanes.unit[g][i].word)));
#else
        write_record(lanes, i, t);
#endif
    }
    // Record `from` copied to `to` by streaming stores.
    static void stream_copy(const TriangleSetup& from, TriangleSetup& to) {
#if defined(__SSE2__)
        auto* out = reinterpret_cast<__m128i*>(&to);
        const auto* in = reinterpret_cast<const __m128i*>(&from);
        for (std::size_t g = 0; g < sizeof(TriangleSetup) / 16; ++g) _mm_stream_si128(out + g, _mm_load_si128(in + g));
#else
        to = from;
#endif
    }

    // The tiles a triangle's inclusive pixel bounds reach, inclusive. Tile sizes are powers of two
    // and the bounds are inside the scissor (non-negative), so a shift finds the tile.
    struct TileSpan {
        int x0, x1, y0, y1;
    };
    // Depth floors (FrontEndChunk::depth_floors) for a depth test that uses them, when the chunk's
    // bins will hold 64 records a tile on average: below that a piece passed over saves less than
    // finding the tile's largest depth costs.
    static bool wants_floors(std::size_t primitives, const FrontEndParams& p) {
        const std::size_t tiles = static_cast<std::size_t>(std::max(1, p.tiles_x)) * static_cast<std::size_t>(std::max(1, p.tiles_y));
        return floors_for(p.state.depth_test) && primitives >= 64 * tiles;
    }
    // A bin's first allocation where the chunk's first draw did not size it (size_first_bins,
    // front_end.cpp): the chunk's primitives shared among the tiles (16 records at least, 1024 at
    // most), where std::vector's growth would start at 1 and double. A first frame grew each of the
    // bunny's bins 10 times or more, allocating, copying and faulting in about twice the records'
    // memory (1,250 allocations at 2 threads): its front end took 4 ms more than a warm frame's
    // (docs/BENCHMARKS.md). Bins that get nothing allocate nothing; a renderer's bins keep their
    // memory from one draw to the next.
    static std::size_t first_bin_capacity(std::size_t primitives, const FrontEndParams& p) {
        const std::size_t tiles = static_cast<std::size_t>(std::max(1, p.tiles_x)) * static_cast<std::size_t>(std::max(1, p.tiles_y));
        return std::clamp<std::size_t>(primitives / tiles, 16, 1024);
    }

    // The chunk's bins, and which tiles pixel bounds reach.
    struct BinGrid {
        int shift;
        std::size_t tiles_x;
        TileBin* bins;
        std::vector<std::uint32_t>* primitives;  // with Primitives
        std::vector<float>* floors;              // the chunk's depth_floors, or null (floors_for)
        std::size_t first_capacity;
        // Tile t's bin, with room for one more record.
        [[gnu::always_inline]] TileBin& bin(std::size_t t) const {
            TileBin& b = bins[t];
            if (b.size() == b.capacity()) [[unlikely]] grow(b, first_capacity);
            return b;
        }
        TileSpan tiles_of(int min_x, int max_x, int min_y, int max_y) const {
            return {min_x >> shift, max_x >> shift, min_y >> shift, max_y >> shift};
        }
        // tiles_of(...).one() in fewer operations: non-negative bounds share their tile exactly
        // when they agree above the tile's bits.
        bool one_tile(int min_x, int max_x, int min_y, int max_y) const {
            return (((min_x ^ max_x) | (min_y ^ max_y)) >> shift) == 0;
        }
        std::size_t tile(int tx, int ty) const { return static_cast<std::size_t>(ty) * tiles_x + static_cast<std::size_t>(tx); }
        std::size_t tile_of_pixel(int x, int y) const { return tile(x >> shift, y >> shift); }
    };
    BinGrid grid_of() const {
        return {std::countr_zero(static_cast<unsigned>(p_.tile_size)), static_cast<std::size_t>(p_.tiles_x),
                out_.bins.data(), out_.primitives.data(), floors_ ? out_.depth_floors.data() : nullptr, first_capacity_};
    }
    [[gnu::noinline]] static void grow(TileBin& bin, std::size_t first_capacity) {
        bin.reserve(std::max(2 * bin.capacity(), first_capacity));
    }

    // Record t, just added to the end of `tile`'s bin, lowers its piece's depth floor (with floors).
    [[gnu::always_inline]] static void note_floor(const BinGrid& grid, std::size_t tile, const TriangleSetup& t) {
        if (grid.floors) note_floor(grid, tile, lowest_depth(t));
    }
    [[gnu::always_inline]] static void note_floor(const BinGrid& grid, std::size_t tile, float low) {
        if (!grid.floors) return;
        std::vector<float>& f = grid.floors[tile];
        if ((grid.bins[tile].size() - 1) % k_bin_piece == 0) f.push_back(low);
        else f.back() = std::min(f.back(), low);
    }

    // Record i of `lanes` into the bin of every tile it reaches: a record that goes to one tile
    // (most) is written straight into its bin (with Stream, by streaming stores).
    // A triangle's tile comes from its kernel (SetupLanes::tile), a segment's from its bounds.
    template <bool Stream = false, bool Segment = Stream>
    [[gnu::always_inline]] void bin_lanes_record(const BinGrid& grid, const SetupLanes& lanes, int i, std::uint32_t primitive) {
        const std::int32_t* bounds = lanes.bounds(i);
        const bool one_tile = Segment ? grid.one_tile(bounds[0], bounds[2], bounds[1], bounds[3]) : lanes.tile[i] >= 0;
        if (one_tile) {
            const std::size_t tile = Segment ? grid.tile_of_pixel(bounds[0], bounds[1]) : static_cast<std::size_t>(lanes.tile[i]);
            TriangleSetup& t = slot<!Stream>(grid, tile, primitive);
            // Noted before the record's bytes are copied: the compiler takes those stores to change
            // the bin's pointers.
            note_floor(grid, tile, Segment ? -std::numeric_limits<float>::infinity() : lanes.floor[i]);
            if constexpr (Stream) stream_record(lanes, i, t);
            else write_record(lanes, i, t);
            return;
        }
        write_record(lanes, i, scratch_[0]);
        bin_across_tiles(scratch_[0], grid.tiles_of(bounds[0], bounds[2], bounds[1], bounds[3]), primitive);
    }

    // The kept records of lanes_ in batch order. Forced inline, each loop with its kind of store (and
    // the grid by value, in registers): a lambda that both called measured slower (the 1M sphere +2 ms).
    template <bool Stream>
    [[gnu::always_inline]] void bin_lanes_records(const BinGrid grid) {
        for (std::uint32_t keep = lanes_.keep; keep != 0; keep &= keep - 1) {
            const int i = std::countr_zero(keep);
            bin_lanes_record<Stream, false>(grid, lanes_, i, Primitives ? primitive_[i] : 0);
        }
    }

    static void write_rect(const PixelRect& r, const ScreenVertex& c, std::uint32_t ref, TriangleSetup& t) {
        for (int k = 0; k < 3; ++k) t.a[k] = 0, t.b[k] = 0, t.e0[k] = 0, t.vertex[k] = ref;
        t.min_x = r.x0, t.min_y = r.y0, t.max_x = r.x1 - 1, t.max_y = r.y1 - 1;
        t.x0 = static_cast<float>(c.x) * (1.0f / k_subpixel_one), t.y0 = static_cast<float>(c.y) * (1.0f / k_subpixel_one);
        t.z0 = c.z, t.dzdx = 0, t.dzdy = 0;
        t.q0 = c.q, t.dqdx = 0, t.dqdy = 0;
        t.dl1dx = 0, t.dl1dy = 0, t.dl2dx = 0, t.dl2dy = 0;
        t.front_facing = true;
        t.small_edges = true;
        t.segment = false;
        t.line_aa = 0;
    }

    // One triangle set up by the scalar code, and binned.
    void set_up_and_bin(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], std::uint32_t primitive) {
        TriangleSetup& t = scratch_[0];
        switch (setup_triangle(v, ref, p_, t)) {
            case SetupResult::culled: ++culled_; return;
            case SetupResult::empty: return;
            case SetupResult::ok: break;
        }
        bin(t, primitive);
        ++set_up_;
    }

    // Record t of triangle `primitive` into the bin of every tile it reaches. A triangle inside one
    // tile (most of them) goes to that tile's bin unexamined. Forced inline into the batch loop: as a
    // call, its entry and exit were a third of its samples.
    [[gnu::always_inline]] void bin(const TriangleSetup& t, std::uint32_t primitive) {
        const BinGrid grid = grid_of();
        if (grid.one_tile(t.min_x, t.max_x, t.min_y, t.max_y)) {
            const std::size_t tile = grid.tile_of_pixel(t.min_x, t.min_y);
            grid.bin(tile).push_back(t);
            if constexpr (Primitives) grid.primitives[tile].push_back(primitive);
            note_floor(grid, tile, t);
            return;
        }
        bin_across_tiles(t, grid.tiles_of(t.min_x, t.max_x, t.min_y, t.max_y), primitive);
    }

    // Out of line: few triangles span tiles, and the batch loop stays small without this one.
    // With shared bins (FrontEndParams::shared_bins), the copies are streaming stores: the bins' lines
    // were last read by whichever thread drew their tiles in the previous draw, and an ordinary store
    // first fetches its line from that core (homer at 2 threads: a tenth of its frame).
    [[gnu::noinline]] void bin_across_tiles(const TriangleSetup& t, TileSpan span, std::uint32_t primitive) {
        if (t.segment) return bin_segment_across_tiles(t, span, primitive);
        const int s = p_.tile_size;
        const BinGrid grid = grid_of();
        const float low = floors_ ? lowest_depth(t) : 0.0f;
        const bool stream = p_.shared_bins;
        for (int ty = span.y0; ty <= span.y1; ++ty)
            for (int tx = span.x0; tx <= span.x1; ++tx) {
                const PixelRect r{tx * s, ty * s, tx * s + s, ty * s + s};
                if (edge_rejects(t, 0, r) || edge_rejects(t, 1, r) || edge_rejects(t, 2, r)) continue;
                const std::size_t tile = grid.tile(tx, ty);
                TriangleSetup& to = slot<false>(grid, tile, primitive);
                note_floor(grid, tile, low);  // before the copy, as in bin_lanes_record
                if (stream) stream_copy(t, to);
                else to = t;
            }
        streamed_ |= stream;
    }
    // A segment's record likewise, stored by streaming stores as add_segments's are. Bounds that
    // reach two tiles (most of the segments that cross tiles) are not tested: they are the pixel
    // centres within the quad's extent, so the quad reaches a column (or row) of centres of each
    // tile, and a tile it missed would cost only its depth pass a record that covers nothing there.
    void bin_segment_across_tiles(const TriangleSetup& t, TileSpan span, std::uint32_t primitive) {
        const int s = p_.tile_size;
        const BinGrid grid = grid_of();
        const bool test = (span.x1 - span.x0) + (span.y1 - span.y0) > 1;
        for (int ty = span.y0; ty <= span.y1; ++ty)
            for (int tx = span.x0; tx <= span.x1; ++tx) {
                if (test && segment_rejects(t, PixelRect{tx * s, ty * s, tx * s + s, ty * s + s})) continue;
                stream_copy(t, slot<false>(grid, grid.tile(tx, ty), primitive));
                note_floor(grid, grid.tile(tx, ty), -std::numeric_limits<float>::infinity());
            }
        streamed_ = true;
    }

    const FrontEndParams& p_;
    FrontEndChunk& out_;
    std::uint64_t set_up_ = 0, culled_ = 0;
    std::size_t first_capacity_;
    bool floors_;
    bool streamed_ = false;
    SetupBatch batch_{};  // zeroed once: lanes past the count then always hold finite values
    SetupLanes lanes_;
    TriangleSetup scratch_[SetupBatch::k_capacity];
    std::uint32_t primitive_[SetupBatch::k_capacity] = {};  // with Primitives: batch triangle i's index in the draw
};


}  // namespace facet::detail
