// facet internals: the hook by which a shader type brings its own compiled visible-pixel pass.
// The renderer's visible-only order ends each tile with detail::shade_visible (fragment.hpp), which
// calls fragment() once per visible pixel of a VisibleTile. A shader type for which
// CompiledVisiblePass is specialized with available = true, and
//   static void run(const S& shader, const VisibleTile& tile, TargetView colour);
// is shaded by its run() instead: the built-in shaders (shaders.hpp) have SIMD kernels compiled into
// the library for every ISA (src/shade/visible_simd*), which compute the same bytes as shade_visible
// over 4 to 16 pixels at a time.
#pragma once

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet::detail {

struct VisibleTile;
struct TargetView;

template <class S>
struct CompiledVisiblePass {
    static constexpr bool available = false;
};

}  // namespace facet::detail
FACET_API_END
