// facet: the parts of a draw call that do not depend on the shader: planning (viewport, tiles,
// batches), running the front end over chunks of triangles and the tile pass over their bins, and
// adding up statistics.
#include "facet/renderer.hpp"

#include "facet/defaults.hpp"

#include <string>

#include "exec/fresh_pages.hpp"
#include "geometry/project.hpp"
#include "tile/passes.hpp"
#include "tile/tile_pass.hpp"

namespace facet {

namespace detail {

void ClipVertices::resize(std::size_t n, int stride_) {
    stride = stride_;
    const auto grow = [](auto& v, std::size_t size) {
        if (v.capacity() < size) reserve_in_huge_pages(v, size);
        v.resize(size);
    };
    grow(pos, n);
    grow(varyings, n * static_cast<std::size_t>(stride_));
    grow(outcode, n);
    grow(screen, n);
}

}  // namespace detail

namespace {

// Triangles per front-end task: enough work to amortize scheduling, and few enough that a small mesh
// (a few hundred triangles) is split between two threads rather than binned by one while the other
// waits. The split does not change the output (bins keep submission order), only the balance between
// threads.
constexpr std::size_t k_min_chunk_triangles = 512;
// Front-end tasks per thread: two; with two threads or more, three for a batch of triangles of at
// least this many a thread. The threads wait at the end of the front end for the last chunk, and
// a chunk of a 1M-triangle batch takes milliseconds: a third of a thread's share instead of a half
// shortens that wait (docs/BENCHMARKS.md, the 1M sphere, session 11). The tiles of smaller batches,
// and of points' and lines' (whose front end is the cheaper part), pay more for the extra bins than
// the shorter chunks save (homer's frame and 1M segments' 2% slower with three).
constexpr std::size_t k_three_chunks_triangles = std::size_t{1} << 18;

// Throws invalid_argument with message() unless ok. The message is built only on failure: draw()
// checks its arguments every call, and must not allocate when they are fine.
template <class Message>
void require(bool ok, const Message& message) {
    if (!ok) throw FacetError(Error{ErrorCode::invalid_argument, message()});
}

}  // namespace

Renderer::Renderer(RendererConfig config)
    : pool_(config.threads),
      tile_size_(config.tile_size),
      batch_size_(resolve_batch_triangles(config.batch_triangles, pool_.size())) {
    const int s = config.tile_size;
    require(s >= 8 && s <= detail::k_max_tile_size && (s & (s - 1)) == 0,
            [&] { return "RendererConfig::tile_size must be a power of two from 8 to 64, got " + std::to_string(s); });
    tiles_ = std::make_unique<detail::TilePass>(pool_.size());
    passes_ = std::make_unique<detail::PassState>();
    require(config.batch_triangles >= 0, [&] {
        return "RendererConfig::batch_triangles must not be negative, got " + std::to_string(config.batch_triangles);
    });
}

Renderer::~Renderer() = default;

Renderer::Plan Renderer::begin_draw(Framebuffer& target, const DrawState& state, const DrawInput& input,
                                    const detail::TileShading& shading, const DrawPasses* passes) {
    Rect vp = state.viewport;
    if (vp.width == 0 && vp.height == 0) vp = Rect{0, 0, target.width(), target.height()};
    require(vp.width > 0 && vp.height > 0, [] { return std::string("draw: the viewport must have a positive size"); });
    require(vp.x >= 0 && vp.y >= 0 && vp.x + vp.width <= k_max_target_size && vp.y + vp.height <= k_max_target_size,
            [] { return "draw: the viewport must lie within [0, " + std::to_string(k_max_target_size) + "] in x and y"; });

    Plan plan;
    detail::FrontEndParams& p = plan.params;
    p.state = state;
    p.scissor = {vp.x, vp.y, std::min(vp.x + vp.width, target.width()), std::min(vp.y + vp.height, target.height())};
    p.vp_x = static_cast<float>(vp.x);
    p.vp_y = static_cast<float>(vp.y);
    p.vp_w = static_cast<float>(vp.width);
    p.vp_h = static_cast<float>(vp.height);
    p.tile_size = tile_size_;
    p.tiles_x = (target.width() + tile_size_ - 1) / tile_size_;
    p.tiles_y = (target.height() + tile_size_ - 1) / tile_size_;
    p.shared_bins = pool_.size() > 1;

    const PrimitiveStyle& style = input.style;
    if (input.topology == Topology::points) {
        require(style.model_scale >= 0 && style.model_scale < 1e30f, [&] {
            return "draw: the point model scale must be finite and not negative, got " + std::to_string(style.model_scale);
        });
        // A size in model units may be any positive number: what is drawn is capped at
        // k_max_point_size pixels (assemble_points), and a product too large for a float is infinite
        // there, which the cap takes too.
        const bool model_units = style.model_scale > 0;
        require(model_units ? style.point_size > 0 && style.point_size < PrimitiveStyle::k_model_point_size_bound
                            : style.point_size > 0 && style.point_size <= PrimitiveStyle::k_max_point_size,
                [&] {
                    return (model_units ? "draw: the point size in model units must be in (0, 1e30), got "
                                        : "draw: the point size must be in (0, 256], got ") +
                           std::to_string(style.point_size);
                });
    }
    require(input.topology != Topology::lines || (style.line_width > 0 && style.line_width <= PrimitiveStyle::k_max_line_width),
            [&] { return "draw: the line width must be in (0, 256], got " + std::to_string(style.line_width); });
    plan.primitive_count = input.primitive_count();
    plan.stride = shading.varyings;
    plan.batch_size = batch_size_;
    plan.chunk_count = 0;
    plan.clear_tiles = state.clear.has_value();
    plan.passes = passes != nullptr;
    if (passes) {
        detail::PassDraw& d = passes_->draw;
        d = {passes, detail::pass_layout(*passes), &passes_->vertices, input.indices, state.front_face, target.width(),
             input.topology};
        passes_->vertices.stride = d.layout.count;
        passes_->vertices.varyings.resize(std::size_t{input.vertex_count} * static_cast<std::size_t>(d.layout.count));
    }
    if (plan.clear_tiles && shading.order == detail::DrawOrder::nothing) {
        target.clear(state.clear->colour, state.clear->depth);
        if (passes) detail::clear_pass_targets(passes->targets, {0, 0, target.width(), target.height()}, target.width());
        plan.clear_tiles = false;
    }
    return plan;
}

void Renderer::run_pass_vertex_stage(std::size_t begin, std::size_t end) {
    detail::run_pass_vertex_stage(*passes_->draw.passes, passes_->draw.layout, begin, end, passes_->vertices);
}

void Renderer::project_vertices(const Vec4* pos, std::size_t begin, std::size_t end, const Plan& plan) {
    detail::project_vertices(pos, vertices_, begin, end, plan.params);
}

void Renderer::run_front_end(const DrawInput& input, Plan& plan, std::size_t first, std::size_t end) {
    const std::size_t count = end - first;
    // The next batch reads the depth this one leaves in the target.
    plan.store_depth = plan.params.state.keep_depth || end < plan.primitive_count;
    const std::size_t by_size = (count + k_min_chunk_triangles - 1) / k_min_chunk_triangles;
    const auto thread_count = static_cast<std::size_t>(threads());
    const bool large = thread_count > 1 && input.topology == Topology::triangles &&
                       count >= k_three_chunks_triangles * thread_count;
    const std::size_t per_thread = large ? 3 : 2;
    plan.chunk_count = std::max<std::size_t>(1, std::min<std::size_t>(by_size, per_thread * thread_count));
    if (chunks_.size() < plan.chunk_count) chunks_.resize(plan.chunk_count);
    const std::size_t tiles = static_cast<std::size_t>(plan.params.tiles_x) * plan.params.tiles_y;
    const std::size_t per_chunk = (count + plan.chunk_count - 1) / plan.chunk_count;
    // Where chunk c starts. Each thread first draws its own share of the chunks, the triangles
    // whose vertices its share of the vertex stage mostly wrote (parallel_for_shares). With three
    // chunks a thread, a share's chunks are smaller one after the other, weights 3, 2, 1: its last
    // chunk, which decides how long one thread waits for the other, is the shortest.
    const auto chunk_start = [&](std::size_t c) {
        if (!large) return std::min(end, first + c * per_chunk);
        std::size_t before = 0;
        for (std::size_t k = 0; k < c; ++k) before += per_thread - k % per_thread;
        return first + count * before / (thread_count * per_thread * (per_thread + 1) / 2);
    };
    pool_.parallel_for_shares(plan.chunk_count, [&](std::size_t c) {
        const std::size_t chunk_first = chunk_start(c);
        const std::size_t chunk_end = chunk_start(c + 1);
        chunks_[c].reset(tiles, plan.stride, plan.passes ? passes_->draw.layout.count : -1);
        detail::run_front_end(vertices_, input, chunk_first, chunk_end, plan.params, chunks_[c],
                              plan.passes ? &passes_->vertices : nullptr);
    });
}

void Renderer::run_tiles(Framebuffer& target, Plan& plan, const detail::TileShading& shading) {
    tiles_->run(pool_, {chunks_.data(), plan.chunk_count, vertices_, plan.params}, target, shading, plan.clear_tiles, plan.store_depth,
                plan.passes ? &passes_->draw : nullptr);
    plan.clear_tiles = false;  // done by the first batch's tiles
}

void Renderer::add_stats(const Plan& plan, DrawStats& total) const {
    for (std::size_t c = 0; c < plan.chunk_count; ++c) total += chunks_[c].stats;
}

}  // namespace facet
