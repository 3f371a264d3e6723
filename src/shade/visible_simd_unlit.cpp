// facet shade: the SIMD visible-pixel pass of the unlit shaders, Normals and VertexColour
// (shade/visible_simd-inl.h has the shared tile loop and what the kernels compute), compiled once
// per ISA by Highway.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_unlit.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lane-wide fragment() of shaders::Normals and shaders::VertexColour.
struct NormalsLanes {
    static constexpr int N = shaders::Normals::k_varyings;
    const shaders::Normals& s;
    ColourLanes operator()(LanesIn<N>& in) const {
        const DF df;
        const Vec3Lanes n = normalize(vec3_lanes<shaders::Normals::Layout, shaders::Varying::normal>(in.v), in.scalar);
        const VF half = hn::Set(df, 0.5f);
        return {hn::Add(half, hn::Mul(half, n.x)), hn::Add(half, hn::Mul(half, n.y)), hn::Add(half, hn::Mul(half, n.z)),
                hn::Set(df, 1.0f)};
    }
};

struct VertexColourLanes {
    static constexpr int N = shaders::VertexColour::k_varyings;
    const shaders::VertexColour& s;
    ColourLanes operator()(LanesIn<N>& in) const { return colour_lanes<shaders::VertexColour::Layout>(in.v); }
};

void ShadeNormals(const shaders::Normals& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, NormalsLanes{s}, tile, target);
}
void ShadeVertexColour(const shaders::VertexColour& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, VertexColourLanes{s}, tile, target);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

FACET_DEFINE_VISIBLE_PASS(Normals, ShadeNormals)
FACET_DEFINE_VISIBLE_PASS(VertexColour, ShadeVertexColour)

}  // namespace facet::detail
#endif
