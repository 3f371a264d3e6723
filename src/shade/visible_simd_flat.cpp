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
    static constexpr int N = shaders::Flat::k_varyings;
    static constexpr int D = 3;  // the world position's derivatives
    const shaders::Flat& s;
    ColourLanes operator()(LanesIn<N, D>& in) const {
        const DF df;
        const Vec3Lanes a{in.ddx[0], in.ddx[1], in.ddx[2]}, b{in.ddy[0], in.ddy[1], in.ddy[2]};
        const Vec3Lanes face{hn::Sub(hn::Mul(a.y, b.z), hn::Mul(a.z, b.y)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(a.x, b.z)),
                             hn::Sub(hn::Mul(a.x, b.y), hn::Mul(a.y, b.x))};
        Vec3Lanes n = normalize(face, in.scalar);
        const Vec3Lanes to_eye{hn::Sub(hn::Set(df, s.u.eye.x), in.v[0]), hn::Sub(hn::Set(df, s.u.eye.y), in.v[1]),
                               hn::Sub(hn::Set(df, s.u.eye.z), in.v[2])};
        n = select(hn::Lt(dot(n, to_eye), hn::Zero(df)), negate(n), n);
        const VF albedo[4] = {in.v[3], in.v[4], in.v[5], in.v[6]};
        return shade(albedo, lambert_term(n, s.u));
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
