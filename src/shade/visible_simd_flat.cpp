// facet shade: the SIMD visible-pixel pass of shaders::Flat (shade/visible_simd-inl.h has the shared
// tile loop and what the kernels compute), compiled once per ISA by Highway.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_flat.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lane-wide fragment() of shaders::Flat: the face normal from the screen derivatives of the
// world position (facet::cross, then normalize), turned toward the eye, lit as Lambert.
struct FlatLanes {
    using Layout = shaders::Flat::Layout;
    static constexpr int N = shaders::Flat::k_varyings;
    static constexpr int D = shaders::Flat::k_derivative_count;  // the world position's derivatives
    static_assert(Layout::through(shaders::Varying::position) <= D);
    const shaders::Flat& s;
    ColourLanes operator()(LanesIn<N, D>& in) const {
        const DF df;
        const Vec3Lanes a = vec3_lanes<Layout, shaders::Varying::position>(in.ddx);
        const Vec3Lanes b = vec3_lanes<Layout, shaders::Varying::position>(in.ddy);
        const Vec3Lanes face{hn::Sub(hn::Mul(a.y, b.z), hn::Mul(a.z, b.y)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(a.x, b.z)),
                             hn::Sub(hn::Mul(a.x, b.y), hn::Mul(a.y, b.x))};
        Vec3Lanes n = normalize(face, in.scalar);
        const Vec3Lanes position = vec3_lanes<Layout, shaders::Varying::position>(in.v);
        const Vec3Lanes to_eye{hn::Sub(hn::Set(df, s.u.eye.x), position.x), hn::Sub(hn::Set(df, s.u.eye.y), position.y),
                               hn::Sub(hn::Set(df, s.u.eye.z), position.z)};
        n = select(hn::Lt(dot(n, to_eye), hn::Zero(df)), negate(n), n);
        return shade(colour_lanes<Layout>(in.v), lambert_term(n, s.u));
    }
};

void ShadeFlat(const shaders::Flat& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, FlatLanes{s}, tile, target);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

FACET_DEFINE_VISIBLE_PASS(Flat, ShadeFlat)

}  // namespace facet::detail
#endif
