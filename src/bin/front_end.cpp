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
// scratch array (it stays in L1) and copied into each bin. With Primitives (a draw with render
// passes), the index of each record's triangle goes beside it, into the chunk's primitives.
template <bool Primitives>
class Emitter {
    static constexpr int k_record_write_distance = 24;

public:
    Emitter(const FrontEndParams& p, FrontEndChunk& out)
        : p_(p), out_(out) {}

    // Triangle `triangle` of the draw, with every vertex inside all clip planes (most of them): set
    // up later with its batch.
    void add_unclipped(const ClipVertices& vertices, const std::uint32_t (&idx)[3], std::uint32_t triangle) {
        const int i = batch_.count;
        for (int k = 0; k < 3; ++k) {
            batch_.v[k][i] = vertices.screen[idx[k]];
            batch_.ref[k][i] = idx[k];
        }
        if constexpr (Primitives) primitive_[i] = triangle;
        if (++batch_.count == SetupBatch::k_capacity) flush();
    }

    // A triangle made by clipping triangle `triangle`: the pending batch goes first, so records keep
    // submission order.
    void emit(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], std::uint32_t triangle) {
        flush();
        set_up_and_bin(v, ref, triangle);
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
        if (!setup_lanes(batch_, p_, lanes_)) {  // one by one, as setup_one_by_one does
            for (int i = 0; i < batch_.count; ++i) {
                const ScreenVertex v[3] = {batch_.v[0][i], batch_.v[1][i], batch_.v[2][i]};
                const std::uint32_t ref[3] = {batch_.ref[0][i], batch_.ref[1][i], batch_.ref[2][i]};
                set_up_and_bin(v, ref, primitive_[i]);
            }
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
                const std::size_t tile = grid.tile_of_pixel(bounds[0], bounds[1]);
                TriangleSetup& t = grid.bins[tile].emplace_back();
                if constexpr (Primitives) grid.primitives[tile].push_back(primitive_[i]);
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
            bin_across_tiles(scratch_[0], grid.tiles_of(bounds[0], bounds[2], bounds[1], bounds[3]),
                             Primitives ? primitive_[i] : 0);
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
        std::vector<std::uint32_t>* primitives;  // with Primitives
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
                out_.bins.data(), out_.primitives.data()};
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
            grid.bins[tile].push_back(t);
            if constexpr (Primitives) grid.primitives[tile].push_back(primitive);
            return;
        }
        bin_across_tiles(t, grid.tiles_of(t.min_x, t.max_x, t.min_y, t.max_y), primitive);
    }

    // Out of line: few triangles span tiles, and the batch loop stays small without this one.
    [[gnu::noinline]] void bin_across_tiles(const TriangleSetup& t, TileSpan span, std::uint32_t primitive) {
        const int s = p_.tile_size;
        const BinGrid grid = grid_of();
        for (int ty = span.y0; ty <= span.y1; ++ty)
            for (int tx = span.x0; tx <= span.x1; ++tx) {
                const PixelRect r{tx * s, ty * s, tx * s + s, ty * s + s};
                if (edge_rejects(t, 0, r) || edge_rejects(t, 1, r) || edge_rejects(t, 2, r)) continue;
                grid.bins[grid.tile(tx, ty)].push_back(t);
                if constexpr (Primitives) grid.primitives[grid.tile(tx, ty)].push_back(primitive);
            }
    }

    const FrontEndParams& p_;
    FrontEndChunk& out_;
    std::uint64_t set_up_ = 0, culled_ = 0;
    SetupBatch batch_{};  // zeroed once: lanes past the count then always hold finite values
    SetupLanes lanes_;
    TriangleSetup scratch_[SetupBatch::k_capacity];
    std::uint32_t primitive_[SetupBatch::k_capacity] = {};  // with Primitives: batch triangle i's index in the draw
};

// A triangle that is not wholly inside the clip volume with valid vertices: rejected, or clipped
// and its pieces emitted. Out of line: most triangles of a mesh never get here.
template <bool Primitives>
[[gnu::noinline]] void assemble_other(const ClipVertices& vertices, const std::uint32_t (&idx)[3], std::uint32_t triangle,
                                      GuardBand guard, const FrontEndParams& p, Emitter<Primitives>& emitter,
                                      FrontEndChunk& out, const ClipPassVaryings* passes) {
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
    const int n = clip_triangle(tri, codes[0] | codes[1] | codes[2], guard, vertices, out.extras, poly, passes);
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
        emitter.emit(v, ref, triangle);
    }
}

// Triangles [first, end) in order, their vertex indices from `index_of`. A triangle whose three
// vertices are in range and inside every clip plane (outcode 0; an invalid vertex's is not) joins
// the set-up batch after one test; the others go to assemble_other.
template <bool Primitives, class IndexOf>
void assemble(const ClipVertices& vertices, std::size_t first, std::size_t end, const IndexOf& index_of,
              GuardBand guard, const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out,
              const ClipPassVaryings* passes) {
    const std::size_t vertex_count = vertices.pos.size();
    const std::uint8_t* outcode = vertices.outcode.data();
    for (std::size_t t = first; t < end; ++t) {
        const std::uint32_t idx[3] = {index_of(t, 0), index_of(t, 1), index_of(t, 2)};
        if (std::max({idx[0], idx[1], idx[2]}) < vertex_count &&
            (outcode[idx[0]] | outcode[idx[1]] | outcode[idx[2]]) == 0) {
            emitter.add_unclipped(vertices, idx, static_cast<std::uint32_t>(t));
            continue;
        }
        assemble_other(vertices, idx, static_cast<std::uint32_t>(t), guard, p, emitter, out, passes);
    }
}

}  // namespace

void FrontEndChunk::reset(std::size_t tile_count, int stride, int pass_stride) {
    extras.pos.clear();
    extras.varyings.clear();
    extras.stride = stride;
    // Bins only grow: a renderer that draws targets of two sizes in turn (a view's supersampled
    // colour and its passes at 1x) keeps the memory of both. The tiles read only the first tile_count.
    if (bins.size() < tile_count) bins.resize(tile_count);
    for (std::size_t t = 0; t < tile_count; ++t) bins[t].clear();
    pass_extras.varyings.clear();
    pass_extras.stride = pass_stride < 0 ? 0 : pass_stride;
    if (pass_stride >= 0) {
        if (primitives.size() < tile_count) primitives.resize(tile_count);
        for (std::size_t t = 0; t < tile_count; ++t) primitives[t].clear();
    }
    stats = {};
}

namespace {

template <bool Primitives>
void run_front_end_of(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                      const FrontEndParams& p, FrontEndChunk& out, const ClipPassVaryings* passes) {
    const GuardBand guard = guard_band(p);
    Emitter<Primitives> emitter(p, out);
    out.stats.triangles_in += end - first;
    if (input.indices.empty()) {
        // Indices past 2^32 - 1 cannot name a vertex (vertex counts are 32-bit): they stay out of range.
        const auto index_of = [](std::size_t t, int k) {
            const std::size_t i = t * 3 + static_cast<std::size_t>(k);
            return i > 0xffffffffu ? 0xffffffffu : static_cast<std::uint32_t>(i);
        };
        assemble(vertices, first, end, index_of, guard, p, emitter, out, passes);
    } else {
        const std::uint32_t* indices = input.indices.data();
        const auto index_of = [indices](std::size_t t, int k) { return indices[t * 3 + static_cast<std::size_t>(k)]; };
        assemble(vertices, first, end, index_of, guard, p, emitter, out, passes);
    }
    emitter.finish();
}

}  // namespace

void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                   const FrontEndParams& p, FrontEndChunk& out, const ClipVertices* pass_vertices) {
    if (!pass_vertices) return run_front_end_of<false>(vertices, input, first, end, p, out, nullptr);
    const ClipPassVaryings passes{*pass_vertices, out.pass_extras};
    run_front_end_of<true>(vertices, input, first, end, p, out, &passes);
}

}  // namespace facet::detail
