// facet bin: the front end of a draw for one range of triangles, and binning into screen tiles.
// In: ClipVertices + indices. Out: FrontEndChunk (set-up triangles, clip-made vertices, per-tile bins).
#include "facet/detail/front_end.hpp"

#include <algorithm>
#include <bit>

#include "geometry/clip.hpp"
#include "geometry/project.hpp"
#include "setup/setup.hpp"

namespace facet::detail {
namespace {

// True when the edge function is negative over the whole rectangle (no pixel of it is inside).
bool edge_rejects(const TriangleSetup& t, int e, const PixelRect& r) {
    // The largest value of a*x + b*y + c over the rectangle is at the corner its gradient points to.
    const std::int64_t x = t.a[e] > 0 ? r.x1 - 1 : r.x0;
    const std::int64_t y = t.b[e] > 0 ? r.y1 - 1 : r.y0;
    return edge_at(t, e, x, y) < 0;
}

// Sets up each triangle and stores its record in the bin of every tile it reaches. Unclipped
// triangles are collected into a batch set up together by the SIMD kernel; the batch is flushed
// before any clipped triangle and at the end, so every bin keeps submission order. A record that
// goes to one tile (most) is written straight into its bin; the others are set up in a small
// scratch array (it stays in L1) and copied into each bin.
class Emitter {
    static constexpr int k_record_write_distance = 24;

public:
    Emitter(const FrontEndParams& p, FrontEndChunk& out)
        : p_(p), out_(out) {}

    // A triangle with every vertex inside all clip planes (most of them): set up later with its batch.
    void add_unclipped(const ClipVertices& vertices, const std::uint32_t (&idx)[3]) {
        const int i = batch_.count;
        for (int k = 0; k < 3; ++k) {
            batch_.v[k][i] = vertices.screen[idx[k]];
            batch_.ref[k][i] = idx[k];
        }
        if (++batch_.count == SetupBatch::k_capacity) flush();
    }

    // A triangle made by clipping: the pending batch goes first, so records keep submission order.
    void emit(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3]) {
        flush();
        TriangleSetup& t = scratch_[0];
        switch (setup_triangle(v, ref, p_, t)) {
            case SetupResult::culled: ++culled_; return;
            case SetupResult::empty: return;
            case SetupResult::ok: break;
        }
        bin(t);
        ++set_up_;
    }

    void finish() {
        flush();
        out_.stats.triangles_rasterized += set_up_;
        out_.stats.triangles_culled += culled_;
    }

private:
    // Sets up the pending batch in one go (SIMD) and bins the survivors in batch order.
    void flush() {
        if (batch_.count == 0) return;
        if (!setup_lanes(batch_, p_, lanes_)) {
            const BatchSetupCounts done = setup_one_by_one(batch_, p_, scratch_);
            culled_ += static_cast<std::uint64_t>(done.culled);
            for (int j = 0; j < done.written; ++j) bin(scratch_[j]);
            set_up_ += static_cast<std::uint64_t>(done.written);
            batch_.count = 0;
            return;
        }
        culled_ += static_cast<std::uint64_t>(std::popcount(lanes_.culled));
        set_up_ += static_cast<std::uint64_t>(std::popcount(lanes_.keep));
        // A local copy: the record copies below may write any byte, so what a member holds would be
        // read again from memory for every triangle.
        const BinGrid grid = grid_of();
        for (std::uint32_t keep = lanes_.keep; keep != 0; keep &= keep - 1) {
            const int i = std::countr_zero(keep);
            const std::int32_t* bounds = lanes_.bounds(i);
            if (grid.one_tile(bounds[0], bounds[2], bounds[1], bounds[3])) {
                TriangleSetup& t = grid.bin_of_pixel(bounds[0], bounds[1]).emplace_back();
                // The bin's lines a few records on, owned before they are written: a bin is a
                // stream the hardware has not learnt, and a store that misses waits for its line
                // (measured 6% of a 1M-triangle frame). Past the allocation, a prefetch does nothing.
                // 24 records (3 KB) on: since records are written as 16-byte copies, 8 was too close
                // (the 1M-triangle sphere's front end 19.8 -> 17.2 ms; 16 to 64 measured the same).
                prefetch_for_write(&t + k_record_write_distance);
                write_record(lanes_, i, t);
                continue;
            }
            write_record(lanes_, i, scratch_[0]);
            bin_across_tiles(scratch_[0], grid.tiles_of(bounds[0], bounds[2], bounds[1], bounds[3]));
        }
        batch_.count = 0;
    }

    // The tiles a triangle's inclusive pixel bounds reach, inclusive. Tile sizes are powers of two
    // and the bounds are inside the scissor (non-negative), so a shift finds the tile.
    struct TileSpan {
        int x0, x1, y0, y1;
    };
    // The chunk's bins, and which tiles pixel bounds reach.
    struct BinGrid {
        int shift;
        std::size_t tiles_x;
        TileBin* bins;
        TileSpan tiles_of(int min_x, int max_x, int min_y, int max_y) const {
            return {min_x >> shift, max_x >> shift, min_y >> shift, max_y >> shift};
        }
        // tiles_of(...).one() in fewer operations: non-negative bounds share their tile exactly
        // when they agree above the tile's bits.
        bool one_tile(int min_x, int max_x, int min_y, int max_y) const {
            return (((min_x ^ max_x) | (min_y ^ max_y)) >> shift) == 0;
        }
        TileBin& bin(int tx, int ty) const {
            return bins[static_cast<std::size_t>(ty) * tiles_x + static_cast<std::size_t>(tx)];
        }
        TileBin& bin_of_pixel(int x, int y) const { return bin(x >> shift, y >> shift); }
    };
    BinGrid grid_of() const {
        return {std::countr_zero(static_cast<unsigned>(p_.tile_size)), static_cast<std::size_t>(p_.tiles_x),
                out_.bins.data()};
    }

    // A triangle inside one tile (most of them) goes to that tile's bin unexamined.
    // Forced inline into the batch loop: as a call, its entry and exit were a third of its samples.
    [[gnu::always_inline]] void bin(const TriangleSetup& t) {
        const BinGrid grid = grid_of();
        if (grid.one_tile(t.min_x, t.max_x, t.min_y, t.max_y)) {
            grid.bin_of_pixel(t.min_x, t.min_y).push_back(t);
            return;
        }
        bin_across_tiles(t, grid.tiles_of(t.min_x, t.max_x, t.min_y, t.max_y));
    }

    // Out of line: few triangles span tiles, and the batch loop stays small without this one.
    [[gnu::noinline]] void bin_across_tiles(const TriangleSetup& t, TileSpan span) {
        const int s = p_.tile_size;
        const BinGrid grid = grid_of();
        for (int ty = span.y0; ty <= span.y1; ++ty)
            for (int tx = span.x0; tx <= span.x1; ++tx) {
                const PixelRect r{tx * s, ty * s, tx * s + s, ty * s + s};
                if (edge_rejects(t, 0, r) || edge_rejects(t, 1, r) || edge_rejects(t, 2, r)) continue;
                grid.bin(tx, ty).push_back(t);
            }
    }

    const FrontEndParams& p_;
    FrontEndChunk& out_;
    std::uint64_t set_up_ = 0, culled_ = 0;
    SetupBatch batch_{};  // zeroed once: lanes past the count then always hold finite values
    SetupLanes lanes_;
    TriangleSetup scratch_[SetupBatch::k_capacity];
};

// A triangle that is not wholly inside the clip volume with valid vertices: rejected, or clipped
// and its pieces emitted. Out of line: most triangles of a mesh never get here.
[[gnu::noinline]] void assemble_other(const ClipVertices& vertices, const std::uint32_t (&idx)[3], GuardBand guard,
                                      const FrontEndParams& p, Emitter& emitter, FrontEndChunk& out) {
    const std::size_t vertex_count = vertices.pos.size();
    std::uint32_t codes[3];
    for (int k = 0; k < 3; ++k) {
        if (idx[k] >= vertex_count || vertices.outcode[idx[k]] == k_outcode_invalid) {
            ++out.stats.triangles_invalid;
            return;
        }
        codes[k] = vertices.outcode[idx[k]];
    }
    if (codes[0] & codes[1] & codes[2]) return;  // wholly outside one plane
    ++out.stats.triangles_clipped;
    const ClipVertex tri[3] = {{vertices.pos[idx[0]], idx[0]}, {vertices.pos[idx[1]], idx[1]},
                               {vertices.pos[idx[2]], idx[2]}};
    ClipVertex poly[k_max_clip_polygon];
    const int n = clip_triangle(tri, codes[0] | codes[1] | codes[2], guard, vertices, out.extras, poly);
    bool poly_finite = true;
    for (int i = 0; i < n; ++i) poly_finite = poly_finite && is_finite(poly[i].pos) && poly[i].pos.w > 0;
    if (!poly_finite) {  // coordinates so large that the intersections overflowed
        ++out.stats.triangles_invalid;
        return;
    }
    ScreenVertex projected[k_max_clip_polygon];
    for (int i = 0; i < n; ++i) projected[i] = project(poly[i].pos, p);
    for (int i = 1; i + 1 < n; ++i) {
        const ScreenVertex v[3] = {projected[0], projected[i], projected[i + 1]};
        const std::uint32_t ref[3] = {poly[0].ref, poly[i].ref, poly[i + 1].ref};
        emitter.emit(v, ref);
    }
}

// Triangles [first, end) in order, their vertex indices from `index_of`. A triangle whose three
// vertices are in range and inside every clip plane (outcode 0; an invalid vertex's is not) joins
// the set-up batch after one test; the others go to assemble_other.
template <class IndexOf>
void assemble(const ClipVertices& vertices, std::size_t first, std::size_t end, const IndexOf& index_of,
              GuardBand guard, const FrontEndParams& p, Emitter& emitter, FrontEndChunk& out) {
    const std::size_t vertex_count = vertices.pos.size();
    const std::uint8_t* outcode = vertices.outcode.data();
    for (std::size_t t = first; t < end; ++t) {
        const std::uint32_t idx[3] = {index_of(t, 0), index_of(t, 1), index_of(t, 2)};
        if (std::max({idx[0], idx[1], idx[2]}) < vertex_count &&
            (outcode[idx[0]] | outcode[idx[1]] | outcode[idx[2]]) == 0) {
            emitter.add_unclipped(vertices, idx);
            continue;
        }
        assemble_other(vertices, idx, guard, p, emitter, out);
    }
}

}  // namespace

void FrontEndChunk::reset(std::size_t tile_count, int stride) {
    extras.pos.clear();
    extras.varyings.clear();
    extras.stride = stride;
    if (bins.size() != tile_count) bins.resize(tile_count);
    for (auto& bin : bins) bin.clear();
    stats = {};
}

void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                   const FrontEndParams& p, FrontEndChunk& out) {
    const GuardBand guard = guard_band(p);
    Emitter emitter(p, out);
    out.stats.triangles_in += end - first;
    if (input.indices.empty()) {
        // Indices past 2^32 - 1 cannot name a vertex (vertex counts are 32-bit): they stay out of range.
        const auto index_of = [](std::size_t t, int k) {
            const std::size_t i = t * 3 + static_cast<std::size_t>(k);
            return i > 0xffffffffu ? 0xffffffffu : static_cast<std::uint32_t>(i);
        };
        assemble(vertices, first, end, index_of, guard, p, emitter, out);
    } else {
        const std::uint32_t* indices = input.indices.data();
        const auto index_of = [indices](std::size_t t, int k) { return indices[t * 3 + static_cast<std::size_t>(k)]; };
        assemble(vertices, first, end, index_of, guard, p, emitter, out);
    }
    emitter.finish();
}

}  // namespace facet::detail
