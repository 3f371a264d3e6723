// facet: the Renderer runs draw calls into a Framebuffer.
//   vertex stage (shader.vertex per vertex, in parallel blocks)
//   -> front end (assemble, clip, cull, project, snap, set up, bin; in parallel chunks)
//   -> tiles (depth of every triangle, then shader.fragment per visible pixel; or per covered pixel
//      when blending or discarding; one thread per tile, in parallel)
// Front end and tiles run in batches of triangles, in submission order (docs/architecture.md).
// Output is identical byte for byte whatever the thread count or tile size: per tile, triangles are
// drawn in submission order, and every value is computed the same way wherever it is computed.
// A Renderer keeps its scratch memory between draws, so steady-state drawing does not allocate.
// It is not itself thread-safe: use one per thread that draws.
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include "facet/api.hpp"
#include "facet/detail/draw_order.hpp"
#include "facet/detail/front_end.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/detail/vertex_stage.hpp"
#include "facet/defaults.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"
#include "facet/passes.hpp"
#include "facet/pipeline.hpp"

// The tile pass and the render passes' state, private to the library (src/tile/): not exported.
namespace facet::detail {
class TilePass;
struct PassState;
}  // namespace facet::detail

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
    ~Renderer();

    int threads() const { return pool_.size(); }
    int tile_size() const { return tile_size_; }
    std::size_t batch_triangles() const { return batch_size_; }  // per batch, all threads together

    // Draws triangles, points or lines (input.topology) with `shader`. Invalid geometry (indices out
    // of range, NaN or infinite positions, zero-area triangles, parts behind the eye) is dropped and
    // counted in the returned stats; the rest renders. Throws FacetError for an empty or off-target
    // viewport, or a point size or line width outside (0, 256] (a point size in model units outside
    // (0, 1e30)). With `passes`,
    // also writes the render passes of the pixels where the draw's triangles end up visible
    // (facet/passes.hpp; its targets of the target's size); without, a draw costs nothing more.
    template <Shader S>
    DrawStats draw(Framebuffer& target, const DrawState& state, const DrawInput& input, const S& shader,
                   const DrawPasses* passes = nullptr);

private:
    struct Plan {
        detail::FrontEndParams params;
        std::size_t primitive_count;  // triangles, points or segments
        int stride;               // varyings per vertex
        std::size_t batch_size;   // triangles per batch
        std::size_t chunk_count;  // of the current batch
        bool clear_tiles;         // DrawState::clear, still to be done by the tiles of the next batch
        bool store_depth;         // the current batch's tiles store their depth (DrawState::keep_depth)
        bool passes;              // the draw writes render passes (passes_)
    };
    // Checks the viewport and plans the draw. A clear that no tile will do (DrawOrder::nothing) is done here.
    Plan begin_draw(Framebuffer& target, const DrawState& state, const DrawInput& input,
                    const detail::TileShading& shading, const DrawPasses* passes);
    // The pass vertex stage (src/tile/passes.hpp) over vertices [begin, end), for a draw with passes.
    void run_pass_vertex_stage(std::size_t begin, std::size_t end);
    template <class S>
    void run_vertex_stage(const S& shader, std::uint32_t vertex_count, const Plan& plan);
    // The projection pass (src/geometry/project.hpp) over vertices [begin, end) of the vertex stage,
    // pos[j] the clip position of vertex begin + j.
    void project_vertices(const Vec4* pos, std::size_t begin, std::size_t end, const Plan& plan);
    void run_front_end(const DrawInput& input, Plan& plan, std::size_t first, std::size_t end);
    // The tile pass (src/tile/) over the current batch's bins.
    void run_tiles(Framebuffer& target, Plan& plan, const detail::TileShading& shading);
    void add_stats(const Plan& plan, DrawStats& total) const;

    detail::ThreadPool pool_;
    int tile_size_;
    std::size_t batch_size_;  // triangles per batch, all threads together
    detail::ClipVertices vertices_;
    std::vector<detail::FrontEndChunk> chunks_;
    std::unique_ptr<detail::TilePass> tiles_;
    std::unique_ptr<detail::PassState> passes_;  // the current draw's render passes, and their vertices
};

// ---- implementation of the templated stages ----

namespace detail {
// Vertices per task in the vertex stage: large enough to amortize scheduling, small enough to balance.
constexpr std::size_t k_vertex_block = 4096;
// A vertex stage of fewer blocks than this many a thread has as many blocks as the next multiple of
// the thread count, of even size (a multiple of 64 vertices, so that no two threads write one cache
// line of the outputs): a mesh of 5,000 vertices is otherwise a block of 4,096 and one of 904, and
// one thread waits for the other (docs/BENCHMARKS.md, small meshes, session 16). The outputs do
// not depend on the blocks.
constexpr std::size_t k_even_vertex_blocks = 4;
constexpr std::size_t k_vertex_align = 64;

// The vertex stage's block size for `vertex_count` vertices on `threads` threads.
inline std::size_t vertex_block(std::size_t vertex_count, std::size_t threads) {
    std::size_t blocks = (vertex_count + k_vertex_block - 1) / k_vertex_block;
    if (threads < 2 || blocks == 0 || blocks >= k_even_vertex_blocks * threads) return k_vertex_block;
    blocks = (blocks + threads - 1) / threads * threads;
    const std::size_t even = (vertex_count + blocks - 1) / blocks;
    return (even + k_vertex_align - 1) / k_vertex_align * k_vertex_align;
}
// Vertices per piece of a compiled vertex stage's block: their clip positions (4 KB) stay in L1
// between the transform and the projection, and are never written to ClipVertices::pos.
constexpr std::size_t k_vertex_piece = 256;

// shader.vertex() for vertices [begin, end) into `vertices`. Flattened: GCC otherwise keeps some of the
// shader's matrix products as calls, depending on what else the caller holds.
template <class S>
[[gnu::flatten]] void run_vertex_shader(const S& shader, std::size_t begin, std::size_t end, ClipVertices& vertices) {
    constexpr int N = S::k_varyings;
    Varyings<N> out;
    for (std::size_t i = begin; i < end; ++i) {
        vertices.pos[i] = shader.vertex(static_cast<std::uint32_t>(i), out);
        float* dst = vertices.varyings.data() + i * N;
        for (int k = 0; k < N; ++k) dst[k] = out[k];
    }
}
}  // namespace detail

// The vertex stage: shader.vertex() per vertex (or the shader's compiled vertex stage), in parallel
// blocks, each block projected as soon as it is done, while it is in the caches. A compiled stage
// projects each piece of its block from a buffer on the stack and leaves ClipVertices::pos unwritten:
// clipping, the only later reader, recomputes the few positions it needs (ClipVertices::recompute).
template <class S>
void Renderer::run_vertex_stage(const S& shader, std::uint32_t vertex_count, const Plan& plan) {
    constexpr int N = S::k_varyings;
    using Compiled = detail::CompiledVertexStage<S>;
    vertices_.resize(vertex_count, N);
    vertices_.recompute = nullptr;
    if constexpr (Compiled::available) {
        vertices_.recompute = [](const void* s, std::uint32_t i) { return Compiled::position(*static_cast<const S*>(s), i); };
        vertices_.source = &shader;
    }
    const std::size_t size = detail::vertex_block(vertex_count, static_cast<std::size_t>(threads()));
    const std::size_t blocks = (vertex_count + size - 1) / size;
    pool_.parallel_for_shares(blocks, [&](std::size_t block) {
        const std::size_t begin = block * size;
        const std::size_t end = std::min<std::size_t>(vertex_count, begin + size);
        if constexpr (Compiled::available) {
            alignas(64) Vec4 clip[detail::k_vertex_piece];
            for (std::size_t first = begin; first < end; first += detail::k_vertex_piece) {
                const std::size_t last = std::min(end, first + detail::k_vertex_piece);
                Compiled::run(shader, first, last, clip, vertices_.varyings.data() + first * N);
                project_vertices(clip, first, last, plan);
            }
        } else {
            detail::run_vertex_shader(shader, begin, end, vertices_);
            project_vertices(vertices_.pos.data() + begin, begin, end, plan);
        }
        if (plan.passes) run_pass_vertex_stage(begin, end);
    });
}

// The pipeline, stage by stage. Front end and tiles run batch by batch, in submission order, so
// every pixel sees the same sequence of triangles and memory stays bounded whatever the draw's size.
template <Shader S>
DrawStats Renderer::draw(Framebuffer& target, const DrawState& given, const DrawInput& input, const S& shader,
                         const DrawPasses* passes) {
    const bool line_aa = input.topology == Topology::lines && input.style.line_aa;
    const DrawState state = line_aa ? detail::line_aa_state(given) : given;  // anti-aliased lines blend
    const detail::TileShading shading = detail::tile_shading(shader, state, input.primitive_count(), line_aa);  // the order
    Plan plan = begin_draw(target, state, input, shading, passes);  // viewport, tiles, batches, passes
    run_vertex_stage(shader, input.vertex_count, plan);             // vertex(), then projection
    DrawStats stats;
    for (std::size_t first = 0; first < plan.primitive_count; first += plan.batch_size) {
        run_front_end(input, plan, first, std::min(plan.primitive_count, first + plan.batch_size));  // set up, bin
        run_tiles(target, plan, shading);  // depth, shading, stores: tile by tile
        add_stats(plan, stats);
    }
    return stats;
}

}  // namespace facet
FACET_API_END
