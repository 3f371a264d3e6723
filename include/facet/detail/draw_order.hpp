// facet internals: a draw's drawing order, decided once per draw (tile_shading), and the shader's
// entry points for it. The tile pass is compiled once (src/tile/), not per shader: it reaches the
// shader only through TileShading, one call per tile in the visible-only order and one per covered
// triangle and tile in the one-pass order, never per pixel; the pixel loops behind those calls are
// the templates of fragment.hpp, where fragment() inlines.
#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/api.hpp"
#include "facet/detail/blend_pass.hpp"
#include "facet/detail/fragment.hpp"
#include "facet/detail/visible_pass.hpp"

FACET_API_BEGIN
namespace facet::detail {

enum class DrawOrder {
    nothing,       // no tile is drawn: no triangles, or DepthTest::never (a clear is done at once)
    one_pass,      // each covered pixel of each triangle in turn: tested, shaded, written (blending,
                   // a shader that can discard or sets k_shade_hidden)
    visible_only,  // per tile, every triangle's depth first, then the shader once per visible pixel
};

// What the tile pass calls of the shader, for the drawing order `order`.
struct TileShading {
    DrawOrder order = DrawOrder::nothing;
    const void* shader = nullptr;  // the S behind the entry points below
    int varyings = 0;              // S::k_varyings
    DepthTest depth_test = DepthTest::less;
    bool depth_write = true;
    // visible_only: the shading pass of one tile, its colours written to `colour` (the target, or the
    // tile's own buffer).
    void (*shade_visible)(const void* shader, const VisibleTile& tile, TargetView colour) = nullptr;
    // one_pass: the covered pixels of triangle t in `tile` tested, shaded and written to the target;
    // with `owner` (a draw with render passes: rows VisibleTile::k_row apart from the tile's corner),
    // `id` is written there for each pixel whose depth it writes.
    void (*shade_covered)(const void* shader, const TriangleSetup& t, const TileCoverage& coverage, PixelRect tile,
                          const float* const (&var)[3], TargetView target, DepthTest test, std::uint32_t* owner,
                          std::uint32_t id) = nullptr;
};

template <class S>
void shade_visible_tile(const void* shader, const VisibleTile& tile, TargetView colour) {
    const S& s = *static_cast<const S*>(shader);
    if constexpr (CompiledVisiblePass<S>::available)
        CompiledVisiblePass<S>::run(s, tile, colour);
    else
        shade_visible(s, tile, colour);
}

template <class S, bool DepthWrite, Blend B>
void shade_covered(const void* shader, const TriangleSetup& t, const TileCoverage& coverage, PixelRect tile,
                   const float* const (&var)[3], TargetView target, DepthTest test, std::uint32_t* owner,
                   std::uint32_t id) {
    shade_tile<S, DepthWrite, B>(*static_cast<const S*>(shader), test, t, coverage, tile, var, target, owner, id);
}

// The drawing order of a draw of `triangles` triangles with `shader` and `state`, and the entry points
// of `shader` for it: the one place where the order is decided. Depth writes and blending become
// template parameters here; the depth test stays a run-time argument of the compiled depth pass and
// of shade_tile (one copy per shader, not five). An anti-aliased line draw (`line_aa`) takes
// shade_tile, which scales alpha by coverage, or the shader's compiled line pass (CompiledLineAaPass)
// where it has one, rather than a compiled blend pass.
template <class S>
TileShading tile_shading(const S& shader, const DrawState& state, std::size_t triangles, bool line_aa = false) {
    TileShading s{.shader = &shader, .varyings = S::k_varyings, .depth_test = state.depth_test,
                  .depth_write = state.depth_write};
    // Each entry point is compiled only for the shaders that can take it: visible-only for those that
    // cannot discard nor ask to see hidden fragments, the one-pass order without blending for the others.
    constexpr bool can_skip_hidden = draws_visible_only<S, Blend::none>();
    if (triangles == 0 || state.depth_test == DepthTest::never) {
        s.order = DrawOrder::nothing;
    } else if (state.blend == Blend::none && can_skip_hidden) {
        s.order = DrawOrder::visible_only;
        if constexpr (can_skip_hidden) s.shade_visible = &shade_visible_tile<S>;
    } else {
        s.order = DrawOrder::one_pass;
        const bool w = state.depth_write;
        if (state.blend == Blend::alpha) {
            s.shade_covered = w ? &shade_covered<S, true, Blend::alpha> : &shade_covered<S, false, Blend::alpha>;
            if constexpr (CompiledBlendPass<S>::available)
                if (!w && !line_aa) s.shade_covered = &CompiledBlendPass<S>::run;
            if constexpr (CompiledLineAaPass<S>::available)
                if (!w && line_aa) s.shade_covered = &CompiledLineAaPass<S>::run;
        } else if constexpr (!can_skip_hidden)
            s.shade_covered = w ? &shade_covered<S, true, Blend::none> : &shade_covered<S, false, Blend::none>;
    }
    return s;
}

}  // namespace facet::detail
FACET_API_END
