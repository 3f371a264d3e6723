// facet: the Renderer runs draw calls into a Framebuffer.
//   vertex stage (shader.vertex per vertex, in parallel blocks)
//   -> front end (assemble, clip, cull, project, snap, set up, bin; in parallel chunks)
//   -> tiles (coverage, depth, then shader.fragment per visible pixel, or per covered pixel when
//      blending or discarding; one thread per tile, in parallel)
// Front end and tiles run in batches of triangles, in submission order (docs/architecture.md).
// Output is identical byte for byte whatever the thread count or tile size: per tile, triangles are
// drawn in submission order, and every value is computed the same way wherever it is computed.
// A Renderer keeps its scratch memory between draws, so steady-state drawing does not allocate.
// It is not itself thread-safe: use one per thread that draws.
#pragma once

#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include "facet/api.hpp"
#include "facet/detail/front_end.hpp"
#include "facet/detail/shade.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/detail/vertex_stage.hpp"
#include "facet/detail/visible_pass.hpp"
#include "facet/defaults.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"
#include "facet/pipeline.hpp"

FACET_API_BEGIN
namespace facet {

// Defaults and the resolution of the zeros: facet/defaults.hpp.
struct RendererConfig {
    int threads = defaults::k_threads;      // 0: one per core
    int tile_size = defaults::k_tile_size;  // pixels, a power of two from 8 to 64
    // Triangles per batch and thread (0: 131072, and at least 1,048,576 per batch). A draw is set up
    // and rasterized one batch at a time, so this bounds the renderer's memory (about 130 bytes per
    // triangle of a batch); the image does not depend on it.
    int batch_triangles = 0;
};

class Renderer {
public:
    explicit Renderer(RendererConfig config = {});

    int threads() const { return pool_.size(); }
    int tile_size() const { return tile_size_; }
    std::size_t batch_triangles() const { return batch_size_; }  // per batch, all threads together

    // Draws triangles with `shader`. Invalid geometry (indices out of range, NaN or infinite
    // positions, zero-area triangles, parts behind the eye) is dropped and counted in the returned
    // stats; the rest renders. Throws FacetError for an empty or off-target viewport.
    template <Shader S>
    DrawStats draw(Framebuffer& target, const DrawState& state, const DrawInput& input, const S& shader);

private:
    struct Plan {
        detail::FrontEndParams params;
        std::size_t triangle_count;
        int stride;               // varyings per vertex
        std::size_t batch_size;   // triangles per batch
        std::size_t chunk_count;  // of the current batch
        std::size_t max_tile_triangles;  // of the current batch: the most triangles binned to one tile
        // DrawState::clear, still to be done by the tiles of the next batch.
        bool clear_tiles = false;
        detail::TargetView clear_target{};
        int target_width = 0, target_height = 0;
        Rgba8 clear_colour;
        float clear_depth = 1.0f;
    };
    Plan plan_draw(const Framebuffer& target, const DrawState& state, const DrawInput& input, int stride);
    // From the bins of the current batch: plan.max_tile_triangles and tile_order_ (see there).
    void plan_tiles(Plan& plan);
    // The projection pass (src/geometry/project.hpp) over vertices [begin, end) of the vertex stage.
    void project_vertices(std::size_t begin, std::size_t end, const Plan& plan);
    void run_front_end(const DrawInput& input, Plan& plan, std::size_t first, std::size_t end);
    void add_stats(const Plan& plan, DrawStats& total) const;

    void prefetch_ahead(const detail::FrontEndChunk& chunk, const detail::TileBin& bin, std::size_t b) const;
    // Every tile in parallel: context = begin(tile, worker, clear), each(context, tile, chunk, bin)
    // for each chunk's non-empty bin of the tile, in submission order, then end(context, tile).
    // `worker` is the pool worker running the tile (ThreadPool::parallel_for), for per-worker scratch.
    // With ContextClears, a context told `clear` starts the tile's colour and depth at the clear
    // values and writes them to the target itself; the tile is not cleared first.
    template <bool ContextClears, class Begin, class Each, class End>
    void walk_tiles(const Plan& plan, const Begin& begin, const Each& each, const End& end);
    // The three vertices' varyings of triangle t of `chunk`.
    void find_varyings(const detail::FrontEndChunk& chunk, const detail::TriangleSetup& t, const float* (&var)[3]) const;
    // The two drawing orders of detail/shade.hpp: one pass (blending, discard), or depth first and
    // the shader once per visible pixel, whose depth test is a run-time choice (one copy per shader).
    template <class S, bool W, Blend B>
    void run_tiles_in_order(Framebuffer& target, const Plan& plan, const S& shader, DepthTest test);
    template <class S>
    void run_tiles_visible_only(Framebuffer& target, const Plan& plan, const S& shader, DepthTest test, bool depth_write);

    detail::ThreadPool pool_;
    int tile_size_;
    std::size_t batch_size_;  // triangles per batch, all threads together
    detail::ClipVertices vertices_;
    std::vector<detail::FrontEndChunk> chunks_;
    // The order in which walk_tiles hands out the tiles of the current batch: the tiles with
    // triangles in index order, and the empty ones spread evenly between them, so that every
    // worker's queue of empty tiles to clear (DeferredFills) grows with the work during which it
    // writes them, rather than one worker being handed the rows above a model and another the
    // model. The image does not depend on the order.
    std::vector<std::uint32_t> tile_order_;
    std::vector<std::unique_ptr<detail::TileVisibility>> tile_scratch_;  // one per pool worker
};

// ---- implementation of the templated stages ----

namespace detail {
// Vertices per task in the vertex stage: large enough to amortize scheduling, small enough to balance.
constexpr std::size_t k_vertex_block = 4096;
}  // namespace detail

// A tile's triangles share vertices with triangles anywhere in the mesh, so the hardware cannot guess
// where the next one's varyings are: fetch them a few triangles ahead. The records are read front to
// back from the bin, but each tile's bin is a new stream the hardware prefetcher has yet to learn:
// fetch them ahead too.
inline void Renderer::prefetch_ahead(const detail::FrontEndChunk& chunk, const detail::TileBin& bin,
                                     std::size_t b) const {
    constexpr std::size_t k_record_distance = 12, k_varyings_distance = 6;
    if (b + k_record_distance < bin.size()) detail::prefetch_record(&bin[b + k_record_distance]);
    if (b + k_varyings_distance < bin.size()) {
        const float* var[3];
        find_varyings(chunk, bin[b + k_varyings_distance], var);
        for (const float* v : var) detail::prefetch(v);
    }
}

namespace detail {
// Fills a rectangle of at most one tile with one colour and depth; with `stream`, past the caches (see
// store_tile_rows), for a rectangle this draw reads no more.
inline void fill_rect(TargetView target, PixelRect r, Rgba8 colour, float depth, bool stream) {
    alignas(64) Rgba8 colour_row[k_max_tile_size];
    alignas(64) float depth_row[k_max_tile_size];
    const int width = r.x1 - r.x0;
    fill_row(colour_row, width, colour);
    std::fill_n(depth_row, width, depth);
    store_tile_rows(colour_row, 0, target.colour + target.at(r.x0, r.y0), r, target.stride, stream);
    store_tile_rows(depth_row, 0, target.depth + target.at(r.x0, r.y0), r, target.stride, stream);
}
}  // namespace detail

template <bool ContextClears, class Begin, class Each, class End>
void Renderer::walk_tiles(const Plan& plan, const Begin& begin, const Each& each, const End& end) {
    const detail::FrontEndParams& p = plan.params;
    pool_.parallel_for(tile_order_.size(), [&](std::size_t n, int worker) {
        const std::size_t tile_index = tile_order_[n];
        const int tx = static_cast<int>(tile_index % p.tiles_x), ty = static_cast<int>(tile_index / p.tiles_x);
        const detail::PixelRect whole{tx * p.tile_size, ty * p.tile_size, std::min((tx + 1) * p.tile_size, plan.target_width),
                                      std::min((ty + 1) * p.tile_size, plan.target_height)};
        const detail::PixelRect tile{std::max(whole.x0, p.scissor.x0), std::max(whole.y0, p.scissor.y0),
                                     std::min(whole.x1, p.scissor.x1), std::min(whole.y1, p.scissor.y1)};
        bool any = tile.x0 < tile.x1 && tile.y0 < tile.y1;
        if (any) {
            any = false;
            for (std::size_t c = 0; c < plan.chunk_count && !any; ++c) any = !chunks_[c].bins[tile_index].empty();
        }
        // DrawState::clear: the whole tile, inside the viewport or not, by this thread, or by a context
        // that keeps the tile itself and starts it at the clear values (no read of the target).
        const bool context_clears = ContextClears && plan.clear_tiles && any && whole.x0 == tile.x0 &&
                                    whole.y0 == tile.y0 && whole.x1 == tile.x1 && whole.y1 == tile.y1;
        // Streamed when no triangle of this draw reaches the tile; the others read it right after.
        // With contexts (TileVisibility) such a tile joins the worker's deferred fills instead.
        if (plan.clear_tiles && !context_clears) {
            if (ContextClears && !any && detail::DeferredFills::fits(plan.clear_target, whole))
                tile_scratch_[static_cast<std::size_t>(worker)]->fills.add(plan.clear_target, whole);
            else
                detail::fill_rect(plan.clear_target, whole, plan.clear_colour, plan.clear_depth, !any);
        }
        if (!any) return;
        auto&& context = begin(tile, worker, context_clears);
        for (std::size_t c = 0; c < plan.chunk_count; ++c) {
            const detail::FrontEndChunk& chunk = chunks_[c];
            const detail::TileBin& bin = chunk.bins[tile_index];
            if (!bin.empty()) each(context, tile, chunk, bin);
        }
        end(context, tile);
    });
}

inline void Renderer::find_varyings(const detail::FrontEndChunk& chunk, const detail::TriangleSetup& t,
                                    const float* (&var)[3]) const {
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t ref = t.vertex[k];
        var[k] = (ref & detail::k_clipped_bit) ? chunk.extras.varyings_of(ref & ~detail::k_clipped_bit)
                                               : vertices_.varyings_of(ref);
    }
}

template <class S, bool W, Blend B>
void Renderer::run_tiles_in_order(Framebuffer& target, const Plan& plan, const S& shader, DepthTest test) {
    const detail::TargetView view{target.colour_data(), target.depth_data(), target.width()};
    walk_tiles<false>(
        plan, [](detail::PixelRect, int, bool) { return detail::TileCoverage{}; },
        [&](detail::TileCoverage& coverage, detail::PixelRect tile, const detail::FrontEndChunk& chunk,
            const detail::TileBin& bin) {
            for (std::size_t b = 0; b < bin.size(); ++b) {
                prefetch_ahead(chunk, bin, b);
                const detail::TriangleSetup& t = bin[b];
                if (!detail::rasterize_tile(t, tile, coverage)) continue;
                const float* var[3];
                find_varyings(chunk, t, var);
                detail::shade_tile<S, W, B>(shader, test, t, coverage, tile, var, view);
            }
        },
        [](detail::TileCoverage&, detail::PixelRect) {});
}

template <class S>
void Renderer::run_tiles_visible_only(Framebuffer& target, const Plan& plan, const S& shader, DepthTest test,
                                      bool depth_write) {
    const detail::TargetView view{target.colour_data(), target.depth_data(), target.width()};
    const detail::ResolveBinKernel resolve_bin = detail::resolve_bin_kernel(test, depth_write);
    const detail::TileVisibility::Clear clear{plan.clear_colour, plan.clear_depth};
    // Every worker's lists sized for the fullest tile now: after the first draw of a scene they no
    // longer grow, whichever tiles each worker is given.
    for (const auto& vis : tile_scratch_) {
        vis->reserve(plan.max_tile_triangles, S::k_varyings);
        vis->fills.start(plan.clear_target, plan.clear_colour, plan.clear_depth, tile_order_.size());
    }
    walk_tiles<true>(
        plan,
        [&](detail::PixelRect tile, int worker, bool clear_tile) -> detail::TileVisibility& {
            detail::TileVisibility& vis = *tile_scratch_[static_cast<std::size_t>(worker)];
            vis.begin(tile, S::k_varyings, view, clear_tile ? &clear : nullptr);
            return vis;
        },
        [&](detail::TileVisibility& vis, detail::PixelRect tile, const detail::FrontEndChunk& chunk,
            const detail::TileBin& bin) {
            // A triangle that passes nowhere now never owns a pixel: it is not listed.
            const std::size_t first = vis.triangles.size();
            resolve_bin(bin.data(), bin.size(), tile, vis);
            vis.write_shading_records<S::k_varyings>(
                first, [&](const detail::TriangleSetup& t, const float* (&var)[3]) { find_varyings(chunk, t, var); });
        },
        [&](detail::TileVisibility& vis, detail::PixelRect tile) {
            vis.end(tile, view, depth_write);
            const detail::TargetView colour = vis.colour_view(tile, view);
            if constexpr (detail::CompiledVisiblePass<S>::available)
                detail::CompiledVisiblePass<S>::run(shader, vis, tile, colour);
            else
                detail::shade_visible(shader, vis, tile, colour);
            vis.store_colour(tile, view);
            detail::fence_fills(vis.fills);
        });
    // The empty tiles the kernels did not get to, before the next batch reads the target.
    bool pending = false;
    for (const auto& vis : tile_scratch_) pending |= vis->fills.pending();
    if (pending) pool_.parallel_for(tile_scratch_.size(), [&](std::size_t w) { detail::drain_fills(tile_scratch_[w]->fills); });
}

template <Shader S>
DrawStats Renderer::draw(Framebuffer& target, const DrawState& state, const DrawInput& input, const S& shader) {
    constexpr int N = S::k_varyings;
    Plan plan = plan_draw(target, state, input, N);
    plan.clear_target = {target.colour_data(), target.depth_data(), target.width()};

    // Vertex stage, then each vertex's outcode and projection.
    vertices_.resize(input.vertex_count, N);
    const std::size_t blocks = (input.vertex_count + detail::k_vertex_block - 1) / detail::k_vertex_block;
    pool_.parallel_for(blocks, [&](std::size_t block) {
        const std::size_t begin = block * detail::k_vertex_block;
        const std::size_t end = std::min<std::size_t>(input.vertex_count, begin + detail::k_vertex_block);
        if constexpr (detail::CompiledVertexStage<S>::available) {
            detail::CompiledVertexStage<S>::run(shader, begin, end, vertices_.pos.data() + begin,
                                                vertices_.varyings.data() + begin * N);
        } else {
            Varyings<N> out;
            for (std::size_t i = begin; i < end; ++i) {
                vertices_.pos[i] = shader.vertex(static_cast<std::uint32_t>(i), out);
                float* dst = vertices_.varyings.data() + i * N;
                for (int k = 0; k < N; ++k) dst[k] = out[k];
            }
        }
        project_vertices(begin, end, plan);
    });

    // Tiles, drawn in order: depth writes and blending become template parameters once here (the
    // depth function stays a run-time argument, tested once per row by shade_tile). Without
    // blending a shader that cannot discard is drawn visible-only.
    constexpr bool can_skip_hidden = detail::draws_visible_only<S, Blend::none>();
    const bool visible_only = can_skip_hidden && state.blend == Blend::none;
    auto with_blend = [&]<bool W>() {
        if (state.blend == Blend::alpha)
            run_tiles_in_order<S, W, Blend::alpha>(target, plan, shader, state.depth_test);
        else if constexpr (!can_skip_hidden)
            run_tiles_in_order<S, W, Blend::none>(target, plan, shader, state.depth_test);
    };
    auto in_order = [&] {
        if (state.depth_write)
            with_blend.template operator()<true>();
        else
            with_blend.template operator()<false>();
    };
    // Front end and tiles run batch by batch: the set-up records of one batch are still in the caches
    // when the tiles read them, and memory stays bounded whatever the size of the draw. Batches
    // are drawn in submission order, so every pixel sees the same sequence of triangles.
    // A clear that no tile pass will do (no triangles, or a depth test that draws nothing) is done now.
    if (plan.clear_tiles && (plan.triangle_count == 0 || state.depth_test == DepthTest::never)) {
        target.clear(state.clear->colour, state.clear->depth);
        plan.clear_tiles = false;
    }
    DrawStats stats;
    for (std::size_t first = 0; first < plan.triangle_count; first += plan.batch_size) {
        run_front_end(input, plan, first, std::min(plan.triangle_count, first + plan.batch_size));
        bool drawn = false;
        if constexpr (can_skip_hidden) {
            if (visible_only) {
                if (state.depth_test != DepthTest::never)
                    run_tiles_visible_only(target, plan, shader, state.depth_test, state.depth_write);
                drawn = true;
            }
        }
        if (!drawn && state.depth_test != DepthTest::never) in_order();
        add_stats(plan, stats);
        plan.clear_tiles = false;  // done by the first batch's tiles
    }
    return stats;
}

}  // namespace facet
FACET_API_END
