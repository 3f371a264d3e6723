// facet: the parts of a draw call that do not depend on the shader: planning (viewport, tiles,
// chunks), running the front end over chunks of triangles, and adding up statistics.
#include "facet/renderer.hpp"

#include "facet/defaults.hpp"

#include <string>

#include "geometry/project.hpp"

namespace facet {
namespace {

// Triangles per front-end task: enough work to amortize scheduling. The split does not change the
// output (bins keep submission order), only the balance between threads.
constexpr std::size_t k_min_chunk_triangles = 2048;

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
    for (int w = 0; w < pool_.size(); ++w) tile_scratch_.push_back(std::make_unique<detail::TileVisibility>());
    require(config.batch_triangles >= 0, [&] {
        return "RendererConfig::batch_triangles must not be negative, got " + std::to_string(config.batch_triangles);
    });
}

Renderer::Plan Renderer::plan_draw(const Framebuffer& target, const DrawState& state, const DrawInput& input,
                                   int stride) {
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

    // A trailing partial triangle (index count not a multiple of 3) is ignored.
    plan.triangle_count = input.indices.empty() ? input.vertex_count / 3 : input.indices.size() / 3;
    plan.stride = stride;
    plan.batch_size = batch_size_;
    plan.chunk_count = 0;
    plan.max_tile_triangles = 0;
    plan.target_width = target.width();
    plan.target_height = target.height();
    if (state.clear) {
        plan.clear_tiles = true;
        plan.clear_colour = to_rgba8(state.clear->colour);
        plan.clear_depth = state.clear->depth;
    }
    return plan;
}

void Renderer::project_vertices(std::size_t begin, std::size_t end, const Plan& plan) {
    detail::project_vertices(vertices_, begin, end, plan.params);
}

void Renderer::run_front_end(const DrawInput& input, Plan& plan, std::size_t first, std::size_t end) {
    const std::size_t count = end - first;
    const std::size_t by_size = (count + k_min_chunk_triangles - 1) / k_min_chunk_triangles;
    plan.chunk_count = std::max<std::size_t>(1, std::min<std::size_t>(by_size, 2 * static_cast<std::size_t>(threads())));
    if (chunks_.size() < plan.chunk_count) chunks_.resize(plan.chunk_count);
    const std::size_t tiles = static_cast<std::size_t>(plan.params.tiles_x) * plan.params.tiles_y;
    const std::size_t per_chunk = (count + plan.chunk_count - 1) / plan.chunk_count;
    pool_.parallel_for(plan.chunk_count, [&](std::size_t c) {
        const std::size_t chunk_first = std::min(end, first + c * per_chunk);
        const std::size_t chunk_end = std::min(end, chunk_first + per_chunk);
        chunks_[c].reset(tiles, plan.stride);
        detail::run_front_end(vertices_, input, chunk_first, chunk_end, plan.params, chunks_[c]);
    });
    plan_tiles(plan);
}

void Renderer::plan_tiles(Plan& plan) {
    const std::size_t tiles = static_cast<std::size_t>(plan.params.tiles_x) * plan.params.tiles_y;
    // One pass over the bins: each tile's triangles counted, the fullest kept, and the busy tiles
    // put first in the array and the empty ones after it, each in index order; then merged.
    plan.max_tile_triangles = 0;
    tile_order_.resize(2 * tiles);
    std::uint32_t* const order = tile_order_.data();
    std::uint32_t* const empty = order + tiles;
    std::size_t busy_count = 0, empty_count = 0;
    for (std::size_t tile = 0; tile < tiles; ++tile) {
        std::size_t n = 0;
        for (std::size_t c = 0; c < plan.chunk_count; ++c) n += chunks_[c].bins[tile].size();
        plan.max_tile_triangles = std::max(plan.max_tile_triangles, n);
        if (n > 0) order[busy_count++] = static_cast<std::uint32_t>(tile);
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
    tile_order_.resize(tiles);
}

void Renderer::add_stats(const Plan& plan, DrawStats& total) const {
    for (std::size_t c = 0; c < plan.chunk_count; ++c) {
        const DrawStats& s = chunks_[c].stats;
        total.triangles_in += s.triangles_in;
        total.triangles_invalid += s.triangles_invalid;
        total.triangles_culled += s.triangles_culled;
        total.triangles_clipped += s.triangles_clipped;
        total.triangles_rasterized += s.triangles_rasterized;
    }
}

}  // namespace facet
