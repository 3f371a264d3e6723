// facet internals: the hook by which a shader type brings its own compiled pass for alpha-blended
// draws without depth writes (the one-pass order, detail/draw_order.hpp). By default such a draw
// runs detail::shade_tile<S, false, Blend::alpha> (fragment.hpp) on each covered triangle and tile.
// A shader type for which CompiledBlendPass is specialized with available = true, and
//   static void run(const void* shader, const TriangleSetup& t, const TileCoverage& coverage,
//                   PixelRect tile, const float* const (&var)[3], TargetView target, DepthTest test,
//                   std::uint32_t* owner, std::uint32_t id);
// (TileShading::shade_covered's signature) is drawn by its run() instead, which computes the same
// bytes (src/shade/blend_simd.cpp: shaders::PbrUnlitBlended, the contact shadow's quad).
// CompiledLineAaPass is the same hook for anti-aliased line draws (line_aa.hpp), whose records
// the default draws by shade_tile with their coverage: a run() of the same signature draws them
// instead, the same bytes (src/shade/line_aa_simd.cpp: the shaders render_scene draws lines with).
#pragma once

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet::detail {

struct TriangleSetup;
struct TileCoverage;
struct PixelRect;
struct TargetView;

template <class S>
struct CompiledBlendPass {
    static constexpr bool available = false;
};

template <class S>
struct CompiledLineAaPass {
    static constexpr bool available = false;
};

}  // namespace facet::detail
FACET_API_END
