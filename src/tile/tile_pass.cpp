// facet tile pass: the walk over a batch's tiles (tile_pass.hpp): their order, how each is cleared,
// and each busy tile drawn in the draw's order, the depth pass and the shading pass of the
// visible-only order or the triangles one by one of the one-pass order.
#include "tile/tile_pass.hpp"

#include <algorithm>
#include <limits>

#include "tile/deferred_fills.hpp"
#include "tile/depth_pass.hpp"
#include "tile/passes.hpp"
#include "tile/tile_buffers.hpp"
#include "tile/tile_store.hpp"

namespace facet::detail {
namespace {

// One tile of a batch.
struct TileJob {
    std::size_t index;  // row-major
    PixelRect whole;    // the tile in the target
    PixelRect rect;     // the part inside the scissor: what the triangles draw
    bool busy;          // rect is not empty and some triangle of the batch is binned to the tile
};

// An entry of TilePass::order_: the tile's index, with k_busy_bit when some chunk binned a triangle to
// it (order_tiles counts them anyway; asking every chunk's bin again per tile was 2% of a small mesh's
// frame, its loads waiting on lines the tile pass had evicted since).
constexpr std::uint32_t k_busy_bit = 1u << 31;

TileJob tile_job(std::uint32_t entry, const TileBatch& batch, int width, int height) {
    const FrontEndParams& p = batch.params;
    const std::size_t index = entry & ~k_busy_bit;
    const int tx = static_cast<int>(index % static_cast<std::size_t>(p.tiles_x));
    const int ty = static_cast<int>(index / static_cast<std::size_t>(p.tiles_x));
    TileJob job{index,
                {tx * p.tile_size, ty * p.tile_size, std::min((tx + 1) * p.tile_size, width),
                 std::min((ty + 1) * p.tile_size, height)},
                {},
                false};
    job.rect = {std::max(job.whole.x0, p.scissor.x0), std::max(job.whole.y0, p.scissor.y0),
                std::min(job.whole.x1, p.scissor.x1), std::min(job.whole.y1, p.scissor.y1)};
    job.busy = (entry & k_busy_bit) != 0 && job.rect.x0 < job.rect.x1 && job.rect.y0 < job.rect.y1;
    return job;
}

// How a tile of a clearing draw (DrawState::clear) is cleared, the whole tile, by the thread that
// draws it. In the visible-only order a busy tile wholly inside the scissor starts its buffers at
// the clear values and writes each pixel once when it is done (TileBuffers::begin), and an empty
// tile whose rows are whole aligned cache lines joins the worker's deferred fills. Other tiles are
// filled now: streamed past the caches when no triangle of this draw reaches them, copied when the
// tile's triangles read them right after.
enum class TileClear { none, by_buffers, deferred, now };

// Whether the whole tile is inside the scissor (the draw's triangles may reach every pixel of it).
bool inside(const TileJob& job) {
    const PixelRect& w = job.whole;
    return job.rect.x0 == w.x0 && job.rect.y0 == w.y0 && job.rect.x1 == w.x1 && job.rect.y1 == w.y1;
}

TileClear tile_clear(const TileJob& job, bool visible_only, TargetView target) {
    const PixelRect& w = job.whole;
    if (visible_only && job.busy && inside(job)) return TileClear::by_buffers;
    if (visible_only && !job.busy && DeferredFills::fits(target, w)) return TileClear::deferred;
    return TileClear::now;
}

// Calls each(chunk, bin) for every chunk's non-empty bin of `tile`, in submission order.
template <class Each>
void for_each_bin(const TileBatch& batch, std::size_t tile, const Each& each) {
    for (std::size_t c = 0; c < batch.chunk_count; ++c) {
        const FrontEndChunk& chunk = batch.chunks[c];
        const TileBin& bin = chunk.bins[tile];
        if (!bin.empty()) each(chunk, bin);
    }
}

// The visible-only order: the depth pass of every bin, then the shader's pass over the VisibleTile
// (and with render passes, theirs).
void draw_visible_only(TileBuffers& buffers, const TileBatch& batch, const TileJob& job, TargetView target,
                       const TileShading& shading, ResolveBinKernel resolve_bin, const TileBuffers::Clear* clear,
                       bool store_depth, const PassDraw* passes, PassRow* pass_rows) {
    const PixelRect tile = job.rect;
    buffers.begin(tile, shading.varyings, target, clear);
    // Under a depth test less or lequal the tile's depth only falls, so its largest depth found once
    // stays an upper bound: a piece whose floor (FrontEndChunk::depth_floors) is above it fails the
    // test at every pixel, would list and write nothing, and is passed over unread (the far side of
    // a closed mesh after its near side). The largest depth is found again only for a piece the last
    // one found does not pass over, and only when a piece was drawn since.
    const bool floors = floors_for(shading.depth_test);
    float ceiling = clear ? clear->depth : std::numeric_limits<float>::infinity();  // a cleared tile's is known
    bool ceiling_fresh = clear != nullptr;
    for_each_bin(batch, job.index, [&](const FrontEndChunk& chunk, const TileBin& bin) {
        const float* floor = nullptr;
        if (floors) {
            const std::vector<float>& f = chunk.depth_floors[job.index];
            if (f.size() == (bin.size() + k_bin_piece - 1) / k_bin_piece) floor = f.data();
        }
        // A bin a piece at a time (the depth pass fetches records ahead past the piece it is given),
        // each piece's pass records written right after its depth pass, while its records are still
        // in L1. A triangle that passes nowhere now never owns a pixel: it is not listed.
        for (std::size_t at = 0; at < bin.size(); at += k_bin_piece) {
            if (floor) {
                const float low = floor[at / k_bin_piece];
                if (!(low > ceiling) && !ceiling_fresh) {
                    ceiling = tile_depth_ceiling(buffers, tile);
                    ceiling_fresh = true;
                }
                if (low > ceiling) continue;
                ceiling_fresh = false;
            }
            const std::size_t first = buffers.triangles.size();
            resolve_bin(bin.data() + at, std::min(k_bin_piece, bin.size() - at), tile, buffers);
            if (passes) write_pass_records(buffers, first, *passes, chunk, bin, chunk.primitives[job.index]);
        }
        buffers.end_bin(chunk.extras);
    });
    // The tile's streamed rows are fenced once per worker at the end of the batch (TilePass::run).
    buffers.end(tile, target, shading.depth_write, store_depth, false);
    buffers.write_shading_records(batch.vertices);
    const VisibleTile visible = buffers.visible(tile);
    shading.shade_visible(shading.shader, visible, buffers.colour_view(tile, target));
    if (passes) write_pass_pixels(visible, buffers.pass_records.data(), buffers.pass_stride, *passes, pass_rows);
    buffers.store_colour(tile, target, false);
}

// A tile's triangles share vertices with triangles anywhere in the mesh, so the hardware cannot guess
// where the next one's varyings are: fetch them a few triangles ahead. The records are read front to
// back from the bin, but each tile's bin is a new stream the hardware prefetcher has yet to learn:
// fetch them ahead too.
void prefetch_ahead(const VaryingsSource& source, const TileBin& bin, std::size_t b) {
    constexpr std::size_t k_record_distance = 12, k_varyings_distance = 6;
    if (b + k_record_distance < bin.size()) prefetch_record(&bin[b + k_record_distance]);
    if (b + k_varyings_distance < bin.size()) {
        const float* var[3];
        source.find(bin[b + k_varyings_distance], var);
        for (const float* v : var) prefetch(v);
    }
}

// The one-pass order: each triangle's coverage, then its covered pixels tested, shaded and written.
// With render passes, each triangle drawn is listed and owns the pixels whose depth it writes; the
// passes are then written from those owners as in the visible-only order.
void draw_one_pass(TileBuffers& buffers, const TileBatch& batch, const TileJob& job, TargetView target,
                   const TileShading& shading, const PassDraw* passes, PassRow* pass_rows) {
    TileCoverage coverage;
    std::uint32_t* owner = passes ? buffers.owner : nullptr;
    if (passes) buffers.begin_owners(job.rect);
    for_each_bin(batch, job.index, [&](const FrontEndChunk& chunk, const TileBin& bin) {
        const VaryingsSource source{batch.vertices, chunk.extras};
        const std::size_t first = buffers.triangles.size();
        for (std::size_t b = 0; b < bin.size(); ++b) {
            prefetch_ahead(source, bin, b);
            const TriangleSetup& t = bin[b];
            if (!rasterize_tile(t, job.rect, coverage)) continue;
            const float* var[3];
            source.find(t, var);
            const auto id = static_cast<std::uint32_t>(buffers.triangles.size());
            if (passes) buffers.triangles.push_back(&t);
            shading.shade_covered(shading.shader, t, coverage, job.rect, var, target, shading.depth_test, owner, id);
        }
        if (passes) write_pass_records(buffers, first, *passes, chunk, bin, chunk.primitives[job.index]);
    });
    if (!passes) return;
    find_owned_pixels(buffers, job.rect);
    write_pass_pixels(buffers.visible(job.rect), buffers.pass_records.data(), buffers.pass_stride, *passes, pass_rows);
}

}  // namespace

TilePass::TilePass(int workers) {
    for (int w = 0; w < workers; ++w) buffers_.push_back(std::make_unique<TileBuffers>());
}

TilePass::~TilePass() = default;

void TilePass::run(ThreadPool& pool, const TileBatch& batch, Framebuffer& target, const TileShading& shading,
                   bool clear, bool store_depth, const PassDraw* passes) {
    if (shading.order == DrawOrder::nothing) return;
    const std::size_t max_tile_triangles = order_tiles(batch);
    const TargetView view{target.colour_data(), target.depth_data(), target.width()};
    const bool visible_only = shading.order == DrawOrder::visible_only;
    const ClearValues clear_values = batch.params.state.clear.value_or(ClearValues{});
    const TileBuffers::Clear clear_to{to_rgba8(clear_values.colour), clear_values.depth};
    ResolveBinKernel resolve_bin = nullptr;
    const int pass_varyings = passes ? passes->layout.count : -1;
    if (visible_only || passes) {
        if (visible_only)
            resolve_bin = resolve_bin_kernel(shading.depth_test, shading.depth_write,
                                             max_tile_triangles <= k_large_triangles_per_tile);
        // Every worker's lists sized for the fullest tile now: after the first draw of a scene they
        // no longer grow, whichever tiles each worker is given.
        for (const auto& b : buffers_) {
            b->reserve(max_tile_triangles, shading.varyings, pass_varyings, batch.chunk_count);
            if (visible_only) b->fills.start(view, clear_to.colour, clear_to.depth, store_depth, order_.size());
        }
    }
    // After its last tile each worker writes the empty tiles its kernels did not get to (before the
    // next batch reads the target; a loop of its own cost a hand-over), and fences its streaming
    // stores, which are weakly ordered: its busy tiles' rows and its deferred fills are made visible
    // before the loop returns. (A fence after every tile waited for that tile's lines to leave the
    // core: 2% of a small mesh's frame.) Each worker starts on its own share of the tiles, about the
    // same tiles every draw (parallel_for_shares).
    const auto fence = [&](int worker) {
        drain_fills(buffers_[static_cast<std::size_t>(worker)]->fills);
        fence_streams();
    };
    pool.parallel_for_shares(order_.size(), [&](std::size_t n, int worker) {
        const TileJob job = tile_job(order_[n], batch, target.width(), target.height());
        TileBuffers& buffers = *buffers_[static_cast<std::size_t>(worker)];
        const TileClear how = clear ? tile_clear(job, visible_only, view) : TileClear::none;
        if (how == TileClear::deferred) buffers.fills.add(view, job.whole);
        if (how == TileClear::now) fill_rect(view, job.whole, clear_to.colour, clear_to.depth, !job.busy);
        // The passes of a busy tile wholly inside the scissor are written whole, row by row, by its
        // pass writer; the others' are cleared first (streamed when no triangle reaches the tile).
        PassRow* pass_rows = clear && passes && job.busy && inside(job) ? &buffers.pass_row : nullptr;
        if (clear && passes && !pass_rows) clear_pass_targets(passes->passes->targets, job.whole, passes->stride, !job.busy);
        if (!job.busy) return;
        if (visible_only)
            draw_visible_only(buffers, batch, job, view, shading, resolve_bin,
                              how == TileClear::by_buffers ? &clear_to : nullptr, store_depth, passes, pass_rows);
        else
            draw_one_pass(buffers, batch, job, view, shading, passes, pass_rows);
    }, fence);
}

std::size_t TilePass::order_tiles(const TileBatch& batch) {
    const std::size_t tiles = static_cast<std::size_t>(batch.params.tiles_x) * batch.params.tiles_y;
    // One pass over the bins: each tile's triangles counted, the fullest kept, and the busy tiles
    // put first in the array and the empty ones after it, each in index order; then merged.
    std::size_t max_tile_triangles = 0;
    order_.resize(2 * tiles);
    std::uint32_t* const order = order_.data();
    std::uint32_t* const empty = order + tiles;
    std::size_t busy_count = 0, empty_count = 0;
    for (std::size_t tile = 0; tile < tiles; ++tile) {
        std::size_t n = 0;
        for (std::size_t c = 0; c < batch.chunk_count; ++c) n += batch.chunks[c].bins[tile].size();
        max_tile_triangles = std::max(max_tile_triangles, n);
        if (n > 0) order[busy_count++] = static_cast<std::uint32_t>(tile) | k_busy_bit;
        else empty[empty_count++] = static_cast<std::uint32_t>(tile);
    }
    // Merged in place from the back: after busy tile k come the empty tiles up to
    // (k + 1) * empty_count / busy_count (all of them before the first when none is busy).
    std::size_t out = tiles, e = empty_count;
    for (std::size_t k = busy_count; k-- > 0;) {
        const std::size_t keep = k * empty_count / busy_count;  // empty tiles that go before busy tile k
        while (e > keep) order[--out] = empty[--e];
        order[--out] = order[k];
    }
    while (e > 0) order[--out] = empty[--e];
    order_.resize(tiles);
    return max_tile_triangles;
}

}  // namespace facet::detail
