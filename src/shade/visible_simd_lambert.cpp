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
// With grey lights the light is computed once for three channels, and with a grey base colour
// (LambertBaseColour) so is the colour: both are the lambert mode's (white key light, no fill, grey
// albedo). The same operations on the same bits: the same bytes. A dark fill light is left out of
// grey lights (fill_is_dark: the same bytes too).
template <class S>
struct LambertLanes {
    static constexpr int N = S::k_varyings;
    S s;  // a copy: the kernel's stores cannot alias it, so its uniforms stay in registers
    bool grey_light = grey_lights(s.u);
    bool no_fill = fill_is_dark(s.u.fill);
    bool grey_colour = grey_light && !S::k_vertex_colours && grey(Vec3{s.u.base_colour.x, s.u.base_colour.y, s.u.base_colour.z});
    Vec3Lanes light(LanesIn<N>& in) const {
        const Vec3Lanes n = normalize(vec3_lanes<typename S::Layout, shaders::Varying::normal>(in.v), in.scalar);
        return lambert_term(n, s.u, grey_light, no_fill);
    }
    ColourLanes operator()(LanesIn<N>& in) const { return shade(albedo_lanes(s, in), light(in)); }
    hn::Vec<DU> rgba8(LanesIn<N>& in) const {
        if (!grey_colour) return to_rgba8((*this)(in));
        const DF df;
        // shade(): albedo.r * light.x, alpha kept.
        return grey_to_rgba8(hn::Mul(hn::Set(df, s.u.base_colour.x), light(in).x), hn::Set(df, s.u.base_colour.w));
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
