// facet shade: the SIMD visible-pixel pass of the Lambert shaders (shade/visible_simd-inl.h
// has the shared tile loop and what the kernels compute), compiled once per ISA by Highway.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_lambert.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cmath>
#include <limits>

#include "facet/image.hpp"
#include "facet/shaders.hpp"
#include "exec/sanitized.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lane-wide fragment() of LambertShader (shaders::Lambert, shaders::LambertBaseColour).
// With grey lights the light is computed once for three channels, and with a grey base colour
// (LambertBaseColour) so is the colour: both are the lambert mode's (white key light, no fill, grey
// albedo). The same operations on the same bits: the same bytes. A dark fill light is left out of
// grey lights (fill_is_dark: the same bytes too).
// Whether the grey colour of grey lights without fill, base * (ambient + (key * k) * diffuse)
// with k = max(dot(n, key), 0) (key * k taken as k when `unit_key`), lies in [-0, 1) at every lane
// the Lambert lanes shade themselves: then to_rgba8's clamps change nothing there. Every factor
// non-negative: the colour grows with k, so its value at the bound of k above (with a margin,
// rounded up) bounds it.
inline bool grey_key_light_below_one(const ShadingUniforms& u, float base, bool unit_key) {
    const Vec3 l = u.key.direction;
    const float factors[] = {base, u.ambient, u.diffuse, u.key.colour.x, l.x, l.y, l.z};
    for (const float f : factors)
        if (!std::isfinite(f)) return false;
    if (base < 0 || u.ambient < 0 || u.diffuse < 0 || u.key.colour.x < 0) return false;
    const double length = std::sqrt(double{l.x} * l.x + double{l.y} * l.y + double{l.z} * l.z);
    const double bound = length * (1.0 + 0x1p-16);
    if (!(bound < 1e30)) return false;  // no unit vector (and the float below must hold it)
    const float k = std::nextafter(static_cast<float>(bound), std::numeric_limits<float>::infinity());
    const float lit = unit_key ? k : u.key.colour.x * k;
    return base * (u.ambient + lit * u.diffuse) < 1.0f;
}

// Every value the lanes compute goes to to_rgba8 through additions, multiplications, max and
// divisions by a positive length, which keep a zero a zero, and to_rgba8 makes -0 and 0 the same
// byte: so a zero's sign may differ from the specification's (k_signed_zeros), and the sums that
// start from 0 there leave it out here. The grey lights without fill (the lambert mode's) take
// key * k as k when the key's colour is 1 (the same bits), leave out the clamps when the colour
// cannot leave [0, 1) (grey_key_light_below_one), and the constant alpha byte of a grey colour is
// quantized once, by to_rgba8 itself.
// With `Known` the lambert mode's case holds (lambert_mode below: grey lights and colour, no fill, a
// key of colour 1, the colour below 1) and the lanes take it as known instead of testing it per block.
template <class S, bool Known = false>
struct LambertLanes {
    static constexpr int N = S::k_varyings;
    static constexpr bool k_signed_zeros = false, k_front_facing = false;
    S s;  // a copy: the kernel's stores cannot alias it, so its uniforms stay in registers
    // The methods are forced inline: GCC called rgba8 out of line from the kernel's block loop once
    // that loop held the finding too (ShadeVisibleTile), its vectors passed through memory.
    bool grey_light = grey_lights(s.u);
    bool no_fill = fill_is_dark(s.u.fill);
    bool grey_colour = Known || (grey_light && !S::k_vertex_colours && grey(Vec3{s.u.base_colour.x, s.u.base_colour.y, s.u.base_colour.z}));
    bool unit_key = s.u.key.colour.x == 1.0f;
    bool below_one = grey_colour && no_fill && grey_key_light_below_one(s.u, s.u.base_colour.x, unit_key);
    std::uint32_t alpha_word = std::uint32_t{to_rgba8(Vec4{0, 0, 0, s.u.base_colour.w}).a} << 24;
    bool lambert_mode() const { return grey_colour && no_fill && unit_key && below_one; }
    HWY_INLINE Vec3Lanes normal(LanesIn<N>& in) const {
        return normalize(vec3_lanes<typename S::Layout, shaders::Varying::normal>(in.v), in.scalar, k_min_normal_length);
    }
    HWY_INLINE Vec3Lanes light(LanesIn<N>& in) const { return lambert_term(normal(in), s.u, grey_light, no_fill); }
    // lambert_term of grey lights without fill, one channel: ambient + (key * k) * diffuse.
    HWY_INLINE VF key_light(LanesIn<N>& in) const {
        const DF df;
        const Vec3Lanes n = normal(in);
        const Vec3 l = s.u.key.direction;
        const VF k = max_zero(hn::Add(hn::Add(hn::Mul(n.x, hn::Set(df, l.x)), hn::Mul(n.y, hn::Set(df, l.y))),
                                      hn::Mul(n.z, hn::Set(df, l.z))));
        const VF lit = Known || unit_key ? k : hn::Mul(hn::Set(df, s.u.key.colour.x), k);
        return hn::Add(hn::Set(df, s.u.ambient), hn::Mul(lit, hn::Set(df, s.u.diffuse)));
    }
    HWY_INLINE ColourLanes operator()(LanesIn<N>& in) const { return shade(albedo_lanes(s, in), light(in)); }
    HWY_INLINE hn::Vec<DU> rgba8(LanesIn<N>& in) const {
        if (!Known && !grey_colour) return to_rgba8((*this)(in));
        const DF df;
        // shade(): albedo.r * light.x, alpha kept.
        const VF c = hn::Mul(hn::Set(df, s.u.base_colour.x), Known || no_fill ? key_light(in) : light(in).x);
        return grey_to_rgba8(Known || below_one ? unorm8_in_range(c) : unorm8(c), hn::Set(DU(), alpha_word));
    }
};

// A copy of the base-colour kernel for the lambert mode (LambertLanes' `Known`): without its four
// tests per block and their other paths the compiler keeps more of the uniforms in registers. Not
// in sanitizer builds, whose kernels are compiled once per shader (CI time): the copy makes the same
// accesses as the general kernel, and the release suite compares both with the specification.
#ifndef FACET_LAMBERT_MODE_KERNEL
#define FACET_LAMBERT_MODE_KERNEL (!FACET_SANITIZED)
#endif

void ShadeLambert(const shaders::Lambert& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, LambertLanes<shaders::Lambert>{s}, tile, target);
}
void ShadeLambertBaseColour(const shaders::LambertBaseColour& s, const VisibleTile& tile,
                            TargetView target) {
    const LambertLanes<shaders::LambertBaseColour> lanes{s};
#if FACET_LAMBERT_MODE_KERNEL
    if (lanes.lambert_mode()) return ShadeVisibleTile(s, LambertLanes<shaders::LambertBaseColour, true>{s}, tile, target);
#endif
    ShadeVisibleTile(s, lanes, tile, target);
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
