// facet shade: the SIMD visible-pixel pass of the Lambert shaders (shade/visible_simd-inl.h
// has the shared tile loop and what the kernels compute), compiled once per ISA by Highway.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_lambert.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lane-wide fragment() of LambertShader (shaders::Lambert, shaders::LambertBaseColour).
template <class S>
struct LambertLanes {
    static constexpr int N = S::k_varyings;
    const S& s;
    ColourLanes operator()(LanesIn<N>& in) const {
        const Vec3Lanes n = normalize(vec3_lanes<typename S::Layout, shaders::Varying::normal>(in.v), in.scalar);
        return shade(albedo_lanes(s, in), lambert_term(n, s.u));
    }
};

void ShadeLambert(const shaders::Lambert& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, LambertLanes<shaders::Lambert>{s}, tile, target);
}
void ShadeLambertBaseColour(const shaders::LambertBaseColour& s, const VisibleTile& tile,
                            TargetView target) {
    ShadeVisibleTile(s, LambertLanes<shaders::LambertBaseColour>{s}, tile, target);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

FACET_DEFINE_VISIBLE_PASS(Lambert, ShadeLambert)
FACET_DEFINE_VISIBLE_PASS(LambertBaseColour, ShadeLambertBaseColour)

}  // namespace facet::detail
#endif
