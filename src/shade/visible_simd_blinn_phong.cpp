// facet shade: the SIMD visible-pixel pass of the Blinn-Phong shaders (shade/visible_simd-inl.h
// has the shared tile loop and what the kernels compute), compiled once per ISA by Highway.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_blinn_phong.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lane-wide fragment() of BlinnPhongShader (shaders::BlinnPhong, shaders::BlinnPhongBaseColour).
template <class S>
struct BlinnPhongLanes {
    static constexpr int N = S::k_varyings;
    const S& s;
    ColourLanes operator()(LanesIn<N>& in) const {
        const DF df;
        const ShadingUniforms& u = s.u;
        using Layout = typename S::Layout;
        Vec3Lanes n = normalize(vec3_lanes<Layout, shaders::Varying::normal>(in.v), in.scalar);
        n = select(in.front_facing, n, negate(n));
        const Vec3Lanes eye = splat(u.eye), position = vec3_lanes<Layout, shaders::Varying::position>(in.v);
        const Vec3Lanes to_eye = normalize(
            {hn::Sub(eye.x, position.x), hn::Sub(eye.y, position.y), hn::Sub(eye.z, position.z)}, in.scalar);
        // shaders::detail::blinn_phong
        const ColourLanes c = shade(albedo_lanes(s, in), lambert_term(n, u));
        const Vec3Lanes key = splat(u.key.direction);
        const Vec3Lanes h = normalize({hn::Add(key.x, to_eye.x), hn::Add(key.y, to_eye.y), hn::Add(key.z, to_eye.z)},
                                      in.scalar);
        const VF s_lanes = hn::Mul(hn::Set(df, u.specular), portable_pow(max_zero(dot(n, h)), u.shininess));
        return {hn::Add(c.r, hn::Mul(s_lanes, hn::Set(df, u.key.colour.x))),
                hn::Add(c.g, hn::Mul(s_lanes, hn::Set(df, u.key.colour.y))),
                hn::Add(c.b, hn::Mul(s_lanes, hn::Set(df, u.key.colour.z))), c.a};
    }
};

void ShadeBlinnPhong(const shaders::BlinnPhong& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, BlinnPhongLanes<shaders::BlinnPhong>{s}, tile, target);
}
void ShadeBlinnPhongBaseColour(const shaders::BlinnPhongBaseColour& s, const VisibleTile& tile,
                               TargetView target) {
    ShadeVisibleTile(s, BlinnPhongLanes<shaders::BlinnPhongBaseColour>{s}, tile, target);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

FACET_DEFINE_VISIBLE_PASS(BlinnPhong, ShadeBlinnPhong)
FACET_DEFINE_VISIBLE_PASS(BlinnPhongBaseColour, ShadeBlinnPhongBaseColour)

}  // namespace facet::detail
#endif
