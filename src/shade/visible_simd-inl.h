// facet shade: the visible-pixel pass (pass two of the visible-only order, detail/fragment.hpp) of the
// built-in shaders as SIMD kernels, compiled once per ISA by Highway and dispatched at run time.
// This header holds what the shader families share (lane helpers, interpolation, the tile loop
// ShadeVisibleTile); each family's fragment() in lanes and its exported kernels are in a file of
// their own, so that the kernels compile in parallel:
//   visible_simd_lambert.cpp      Lambert, LambertBaseColour
//   visible_simd_blinn_phong.cpp  BlinnPhong, BlinnPhongBaseColour
//   visible_simd_unlit.cpp        Normals, VertexColour
//   visible_simd_flat.cpp         Flat (reads the position's derivatives: LanesIn::ddx, ddy)
//   visible_simd_pbr.cpp          Pbr, PbrNormalMapped (the lit mode; reads the uv derivatives)
// In: a VisibleTile (which triangle owns each pixel, and each triangle's shading record).
// Out: the colour of every visible pixel of the tile.
//
// A vector of pixels of one row is shaded at once: each lane takes the record of the triangle that
// owns its pixel (one broadcast per triangle present in the vector), then the lanes interpolate the
// varyings and run the shader's arithmetic. Every lane performs the operations
// of fragment_at and of the shader's fragment() in the same order with the same rounding (no FMA:
// the project builds with -ffp-contract=off and Highway's Mul and Add round separately; sqrt and
// division are correctly rounded everywhere), so the bytes are those of the scalar specification,
// shade_visible. What has no exact vector form goes through the specification pixel by pixel: the
// rare cases of normalize (zero, non-finite or overflowing vectors) and the columns past the
// last whole vector of a row.
//
// A Highway "-inl.h" header: included once per target by each kernel file's foreach_target.h
// pass (the guard toggles with HWY_TARGET_TOGGLE), and the definitions live in that target's
// namespace.

// Not per target: the dispatching definition of CompiledVisiblePass<S>::run for a kernel exported
// with HWY_EXPORT (used by the kernel files under #if HWY_ONCE). "scalar" (facet/isa.hpp) runs the
// specification itself.
#ifndef FACET_SHADE_VISIBLE_SIMD_DISPATCH_
#define FACET_SHADE_VISIBLE_SIMD_DISPATCH_
namespace facet::detail {
// Whether the CPU has AVX-512's conflict detection (vpconflictd), which Highway's AVX3 target does
// not require: every AVX-512 CPU with the byte and word instructions has it, but the kernels ask.
inline bool cpu_has_conflict_detection() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool has = __builtin_cpu_supports("avx512cd");
    return has;
#else
    return false;
#endif
}
}  // namespace facet::detail
#define FACET_DEFINE_VISIBLE_PASS(S, KERNEL)                                                                   \
    HWY_EXPORT(KERNEL);                                                                                      \
    void CompiledVisiblePass<shaders::S>::run(const shaders::S& shader, const VisibleTile& tile,             \
                                              TargetView target) {                                           \
        if (use_scalar_kernels()) return shade_visible(shader, tile, target);                                \
        HWY_DYNAMIC_DISPATCH(KERNEL)(shader, tile, target);                                                  \
    }
#endif

#if defined(FACET_SHADE_VISIBLE_SIMD_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FACET_SHADE_VISIBLE_SIMD_INL_H_
#undef FACET_SHADE_VISIBLE_SIMD_INL_H_
#else
#define FACET_SHADE_VISIBLE_SIMD_INL_H_
#endif

#include <hwy/highway.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "facet/detail/fragment.hpp"
#include "facet/shaders.hpp"
#include "tile/stream_fill-inl.h"
#include "simd/mask_bits-inl.h"
#include "simd/masked_compare-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;

struct Vec3Lanes {
    VF x, y, z;
};
struct ColourLanes {
    VF r, g, b, a;
};

HWY_INLINE Vec3Lanes splat(Vec3 v) {
    const DF df;
    return {hn::Set(df, v.x), hn::Set(df, v.y), hn::Set(df, v.z)};
}

// facet::dot: the sum starts from 0, as there.
HWY_INLINE VF dot(const Vec3Lanes& a, const Vec3Lanes& b) {
    const DF df;
    return hn::Add(hn::Add(hn::Add(hn::Zero(df), hn::Mul(a.x, b.x)), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}

// x86's max and min return their second operand unless the first is greater (max) or less (min):
// a NaN in either, or two equal values (-0 and 0), give the second. So Max(a, b) is exactly
// a > b ? a : b, and Min(a, b) a < b ? a : b, in one instruction instead of a compare and a select.
// Highway's portable Max and Min do not promise that: other targets compare and select.
HWY_INLINE VF greater_or_second(VF a, VF b) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    return hn::Max(a, b);
#else
    return hn::IfThenElse(hn::Gt(a, b), a, b);
#endif
}
HWY_INLINE VF less_or_second(VF a, VF b) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    return hn::Min(a, b);
#else
    return hn::IfThenElse(hn::Lt(a, b), a, b);
#endif
}

// std::max(v, 0.0f): v unless v < 0, i.e. unless 0 > v (so NaN stays NaN).
HWY_INLINE VF max_zero(VF v) { return greater_or_second(hn::Zero(DF()), v); }

// facet::dot(a, a) without the sum's leading 0 +, which changes no bit here: a square is never -0.
HWY_INLINE VF dot_self(const Vec3Lanes& a) {
    return hn::Add(hn::Add(hn::Mul(a.x, a.x), hn::Mul(a.y, a.y)), hn::Mul(a.z, a.z));
}

// facet::normalize's common case, a / length(a). Lanes where the length is zero, infinite or NaN
// need normalize_rare: they are added to `scalar`, whose pixels are shaded again by the specification.
// With `min_length`, lanes whose length is not above it are left to the specification too (exact
// either way; a kernel may need the lengths it keeps to be in the normal range).
HWY_INLINE Vec3Lanes normalize(const Vec3Lanes& a, MF& scalar, float min_length = 0.0f) {
    const DF df;
    const VF l = hn::Sqrt(dot_self(a));
    const MF ok = and_compare<Compare::gt>(df, hn::Lt(l, hn::Set(df, std::numeric_limits<float>::infinity())), l,
                                           hn::Set(df, min_length));
    scalar = hn::Or(scalar, hn::Not(ok));
    return {hn::Div(a.x, l), hn::Div(a.y, l), hn::Div(a.z, l)};
}

HWY_INLINE Vec3Lanes negate(const Vec3Lanes& a) { return {hn::Neg(a.x), hn::Neg(a.y), hn::Neg(a.z)}; }

HWY_INLINE Vec3Lanes select(MF m, const Vec3Lanes& a, const Vec3Lanes& b) {
    return {hn::IfThenElse(m, a.x, b.x), hn::IfThenElse(m, a.y, b.y), hn::IfThenElse(m, a.z, b.z)};
}

// facet::portable_pow (math/portable_pow.hpp), operation for operation.
HWY_INLINE VF portable_log2(VF x) {
    const DF df;
    const DU du;
    const DI di;
    const auto bits = hn::BitCast(du, x);
    VF e = hn::ConvertTo(df, hn::Sub(hn::BitCast(di, hn::ShiftRight<23>(bits)), hn::Set(di, 127)));
    VF m = hn::BitCast(df, hn::Or(hn::And(bits, hn::Set(du, 0x007fffffu)), hn::Set(du, 0x3f800000u)));
    const MF big = hn::Gt(m, hn::Set(df, k_sqrt2));
    m = hn::IfThenElse(big, hn::Mul(m, hn::Set(df, 0.5f)), m);
    e = hn::IfThenElse(big, hn::Add(e, hn::Set(df, 1.0f)), e);
    const VF one = hn::Set(df, 1.0f);
    const VF t = hn::Div(hn::Sub(m, one), hn::Add(m, one));
    const VF t2 = hn::Mul(t, t);
    auto term = [&](float c, VF rest) { return hn::Add(hn::Set(df, c), hn::Mul(t2, rest)); };
    const VF p = term(k_log2_c1, term(k_log2_c3, term(k_log2_c5, term(k_log2_c7, hn::Set(df, k_log2_c9)))));
    return hn::Add(e, hn::Mul(t, p));
}

HWY_INLINE VF portable_exp2(VF z) {
    const DF df;
    const DI di;
    const VF i = hn::Round(z);  // to nearest, ties to even: std::nearbyint in the default rounding mode
    const VF f = hn::Sub(z, i);
    auto term = [&](float c, VF rest) { return hn::Add(hn::Set(df, c), hn::Mul(f, rest)); };
    const VF p = term(1.0f, term(k_exp2_c1, term(k_exp2_c2, term(k_exp2_c3, term(k_exp2_c4, term(k_exp2_c5,
                     term(k_exp2_c6, hn::Set(df, k_exp2_c7))))))));
    const auto n = hn::ConvertTo(di, i);
    const auto half = hn::ShiftRight<1>(n);  // arithmetic: floor(n / 2)
    const VF s1 = hn::BitCast(df, hn::ShiftLeft<23>(hn::Add(half, hn::Set(di, 127))));
    const VF s2 = hn::BitCast(df, hn::ShiftLeft<23>(hn::Add(hn::Sub(n, half), hn::Set(di, 127))));
    return hn::Mul(hn::Mul(p, s1), s2);
}

HWY_INLINE VF portable_pow(VF x, float y) {
    const DF df;
    if (y == 0.0f) return hn::Set(df, 1.0f);
    const VF zero = hn::Zero(df), inf = hn::Set(df, std::numeric_limits<float>::infinity());
    const MF subnormal = hn::Lt(x, hn::Set(df, 0x1p-126f));
    const VF scaled = hn::IfThenElse(subnormal, hn::Mul(x, hn::Set(df, 0x1p23f)), x);
    const VF bias = hn::IfThenElseZero(subnormal, hn::Set(df, 23.0f));
    const VF z = hn::Mul(hn::Set(df, y), hn::Sub(portable_log2(scaled), bias));
    const MF nan_z = hn::Ne(z, z);
    VF r = hn::IfThenElse(hn::Lt(z, hn::Set(df, -126.0f)), zero, portable_exp2(z));
    r = hn::IfThenElse(hn::Lt(z, hn::Set(df, 128.0f)), r, hn::IfThenElse(nan_z, z, inf));
    r = hn::IfThenElse(hn::Eq(x, inf), y > 0.0f ? inf : zero, r);
    r = hn::IfThenElse(hn::Eq(x, zero), y > 0.0f ? zero : inf, r);
    return hn::IfThenElse(hn::Ge(x, zero), r, hn::Set(df, std::numeric_limits<float>::quiet_NaN()));
}

// Whether the three channels of c have the same bits: then the same arithmetic on each channel
// gives each the same result, and it need be done once.
inline bool grey(Vec3 c) {
    return std::bit_cast<std::uint32_t>(c.x) == std::bit_cast<std::uint32_t>(c.y) &&
           std::bit_cast<std::uint32_t>(c.y) == std::bit_cast<std::uint32_t>(c.z);
}
// Whether both lights are grey (grey above): the usual white key light and no fill.
inline bool grey_lights(const ShadingUniforms& u) { return grey(u.key.colour) && grey(u.fill.colour); }

// Whether a Lambert kernel may leave out the fill light (lambert_term's `no_fill`): its colour is
// zero and its direction finite and small. Then for a normal of length 1 (the lanes' normalize
// leaves the others to the specification) f = max(dot(n, fill), 0) is finite, fill * f is a zero,
// and adding it changes the light at most by the sign of a zero, which to_rgba8 makes 0 either way
// (an albedo times it is a zero or the same NaN; both become 0). Only for shaders whose light goes
// through shade() straight to to_rgba8.
inline bool fill_is_dark(const DirectionalLight& fill) {
    constexpr float k_small = 1e30f;  // |n_i| <= 2 after normalize: the dot product stays finite
    auto small = [](float v) { return std::fabs(v) <= k_small; };  // false for NaN
    return fill.colour.x == 0.0f && fill.colour.y == 0.0f && fill.colour.z == 0.0f && small(fill.direction.x) &&
           small(fill.direction.y) && small(fill.direction.z);
}

// shaders::detail::lambert_term: ambient + (key * k + fill * f) * diffuse, per channel; with
// `grey_light` (grey_lights(u)) one channel computed for all three; with `no_fill` (fill_is_dark(u.fill))
// ambient + (key * k) * diffuse.
HWY_INLINE Vec3Lanes lambert_term(const Vec3Lanes& n, const ShadingUniforms& u, bool grey_light = false,
                                  bool no_fill = false) {
    const DF df;
    const VF ambient = hn::Set(df, u.ambient), diffuse = hn::Set(df, u.diffuse);
    const VF k = max_zero(dot(n, splat(u.key.direction)));
    if (grey_light && no_fill) {
        const VF c = hn::Add(ambient, hn::Mul(hn::Mul(hn::Set(df, u.key.colour.x), k), diffuse));
        return {c, c, c};
    }
    const VF f = max_zero(dot(n, splat(u.fill.direction)));
    auto channel = [&](float key, float fill) {
        return hn::Add(ambient, hn::Mul(hn::Add(hn::Mul(hn::Set(df, key), k), hn::Mul(hn::Set(df, fill), f)), diffuse));
    };
    if (grey_light) {
        const VF c = channel(u.key.colour.x, u.fill.colour.x);
        return {c, c, c};
    }
    return {channel(u.key.colour.x, u.fill.colour.x), channel(u.key.colour.y, u.fill.colour.y),
            channel(u.key.colour.z, u.fill.colour.z)};
}

// shaders::detail::shade: albedo times light, alpha kept.
HWY_INLINE ColourLanes shade(const ColourLanes& albedo, const Vec3Lanes& light) {
    return {hn::Mul(albedo.r, light.x), hn::Mul(albedo.g, light.y), hn::Mul(albedo.b, light.z), albedo.a};
}

// What each lane of a row knows, for the shaders below: its varyings (and the screen derivatives of
// the first D of them), whether its triangle faces the viewer, which lanes are visible, and which
// must be redone by the specification.
template <int N, int D = 0>
struct LanesIn {
    VF v[N > 0 ? N : 1];
    VF ddx[D > 0 ? D : 1], ddy[D > 0 ? D : 1];
    MF front_facing;
    MF visible;
    MF scalar;
};

// Varying v of a shader with varyings Layout (shaders::VaryingLayout), one vector per float, from
// `lanes` (LanesIn::v, or the derivatives ddx and ddy).
template <class Layout, shaders::Varying v>
HWY_INLINE Vec3Lanes vec3_lanes(const VF* lanes) {
    constexpr int at = Layout::at(v);
    static_assert(at >= 0 && shaders::varying_width(v) == 3, "a three-float varying of the shader");
    return {lanes[at], lanes[at + 1], lanes[at + 2]};
}
template <class Layout>
HWY_INLINE ColourLanes colour_lanes(const VF* lanes) {
    constexpr int at = Layout::at(shaders::Varying::colour);
    static_assert(at >= 0, "the shader has a colour varying");
    return {lanes[at], lanes[at + 1], lanes[at + 2], lanes[at + 3]};
}

// The albedo lanes of a LambertShader or BlinnPhongShader: its colour varying, or its base colour.
template <class S, int N>
HWY_INLINE ColourLanes albedo_lanes(const S& s, const LanesIn<N>& in) {
    const DF df;
    if constexpr (S::Layout::has(shaders::Varying::colour)) return colour_lanes<typename S::Layout>(in.v);
    else {
        const Vec4& c = s.u.base_colour;
        return {hn::Set(df, c.x), hn::Set(df, c.y), hn::Set(df, c.z), hn::Set(df, c.w)};
    }
}

// static_cast<int> of lanes known to lie in [0, 2^31): on x86 the truncating conversion alone.
// (Highway's ConvertTo adds four operations per vector that saturate lanes out of range, which
// these never are: 16 of a block's few hundred instructions in to_rgba8.)
HWY_INLINE hn::Vec<DI> truncate_in_range(VF v) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    return hn::Vec<DI>{_mm512_cvttps_epi32(v.raw)};
#elif HWY_ARCH_X86 && HWY_TARGET == HWY_AVX2
    return hn::Vec<DI>{_mm256_cvttps_epi32(v.raw)};
#elif HWY_ARCH_X86 && (HWY_TARGET == HWY_SSE4 || HWY_TARGET == HWY_SSSE3)
    return hn::Vec<DI>{_mm_cvttps_epi32(v.raw)};
#else
    return hn::ConvertTo(DI(), v);
#endif
}

// unorm8 (below) of lanes known to lie in [-0, 1), where its clamps change nothing (-0 and 0 both
// give 0): scale and round. Other lanes get any value.
HWY_INLINE hn::Vec<DU> unorm8_in_range(VF v) {
    const DF df;
    return hn::BitCast(DU(), truncate_in_range(hn::Add(hn::Mul(v, hn::Set(df, 255.0f)), hn::Set(df, 0.5f))));
}
// to_rgba8 of one channel, as an integer in [0, 255]: clamp to [0, 1] (NaN to 0), scale, round.
HWY_INLINE hn::Vec<DU> unorm8(VF v) {
    const DF df;
    v = greater_or_second(v, hn::Zero(df));
    return unorm8_in_range(less_or_second(v, hn::Set(df, 1.0f)));
}

// Rgba8 in memory order r, g, b, a: one little-endian 32-bit word per pixel.
HWY_INLINE hn::Vec<DU> to_rgba8(const ColourLanes& c) {
    return hn::Or(hn::Or(unorm8(c.r), hn::ShiftLeft<8>(unorm8(c.g))),
                  hn::Or(hn::ShiftLeft<16>(unorm8(c.b)), hn::ShiftLeft<24>(unorm8(c.a))));
}
// to_rgba8 of a grey colour: r, g and b all the byte `grey` (unorm8 of the channel), alpha the byte
// of `alpha_word` (its alpha byte in place, the others 0). The grey byte is copied to the other two
// by one byte shuffle.
HWY_INLINE hn::Vec<DU> grey_to_rgba8(hn::Vec<DU> grey, hn::Vec<DU> alpha_word) {
#if HWY_TARGET == HWY_SCALAR  // (no byte vectors)
    return hn::Or(hn::Or(grey, hn::ShiftLeft<8>(grey)), hn::Or(hn::ShiftLeft<16>(grey), alpha_word));
#else
    const hn::Repartition<std::uint8_t, DU> d8;
    constexpr std::size_t bytes = hn::MaxLanes(d8);
    HWY_ALIGN std::uint8_t spread[bytes];  // per 32-bit lane: its byte 0 three times, then zero
    for (std::size_t b = 0; b < bytes; ++b) spread[b] = b % 4 < 3 ? static_cast<std::uint8_t>(b % 16 / 4 * 4) : 0x80;
    const auto c = hn::BitCast(d8, grey);
    return hn::Or(hn::BitCast(DU(), hn::TableLookupBytesOr0(c, hn::Load(d8, spread))), alpha_word);
#endif
}

// The largest normal length the Lambert lanes leave to the specification, besides zero and
// non-finite ones: above it every square and sum of normalize is in the normal float range, so
// the normalized vector's length is at most 1 + 5 * 2^-24 and dot(n, key) at most
// |key| (1 + 9 * 2^-24) (Cauchy-Schwarz and each operation's rounding).
constexpr float k_min_normal_length = 0x1p-60f;

// For the blended kernels (blend_simd.cpp, line_aa_simd.cpp), which follow the one-pass order's pixel
// loop (fragment.hpp's shade_covered_pixels):
// depth_at in lanes, at (dx, dy) from the triangle's (x0, y0): its depth plane clamped to [0, 1].
HWY_INLINE VF depth_lanes(const TriangleSetup& t, VF dx, VF dy) {
    const DF df;
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
    const VF z = hn::Add(hn::Add(hn::Set(df, t.z0), hn::Mul(hn::Set(df, t.dzdx), dx)), hn::Mul(hn::Set(df, t.dzdy), dy));
    return hn::IfThenElse(hn::Lt(z, zero), zero, hn::IfThenElse(hn::Gt(z, one), one, z));
}
// depth_passes_in in lanes, for a depth test given by its depth_pass_set: each outcome's mask is all
// lanes or none.
struct DepthTestLanes {
    MF lt, eq, gt, unordered;
    explicit DepthTestLanes(std::uint32_t pass_set) {
        const DF df;
        const MF none = hn::FirstN(df, 0), all = hn::Not(none);
        lt = (pass_set >> 1) & 1u ? all : none, eq = (pass_set >> 2) & 1u ? all : none;
        gt = (pass_set >> 4) & 1u ? all : none, unordered = pass_set & 1u ? all : none;
    }
    HWY_INLINE MF passes(VF z, VF stored) const {
        const MF z_lt = hn::Lt(z, stored), z_eq = hn::Eq(z, stored), z_gt = hn::Gt(z, stored);
        return hn::Or(hn::Or(hn::And(z_lt, lt), hn::And(z_eq, eq)),
                      hn::Or(hn::And(z_gt, gt), hn::AndNot(hn::Or(hn::Or(z_lt, z_eq), z_gt), unordered)));
    }
};
// The 8-bit channel at `shift` of packed Rgba8 lanes, as to_vec4 reads it: c / 255.
HWY_INLINE VF unpack_channel(hn::Vec<DU> packed, int shift) {
    const DF df;
    const DU du;
    const auto c = hn::And(hn::ShiftRightSame(packed, shift), hn::Set(du, 0xffu));
    return hn::Div(hn::ConvertTo(df, hn::BitCast(DI(), c)), hn::Set(df, 255.0f));
}
// The blend's alpha, as shade_covered_pixels: a > 0 ? (a < 1 ? a : 1) : 0 (NaN to 0).
HWY_INLINE VF blend_alpha(VF a) {
    const DF df;
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
    return hn::IfThenElse(hn::Gt(a, zero), hn::IfThenElse(hn::Lt(a, one), a, one), zero);
}
// The alpha blend of colour (r, g, b) at alpha a (in [0, 1]) over the packed Rgba8 lanes `dst`, as
// shade_covered_pixels: c * a + dst * (1 - a), alpha a + dst.a * (1 - a).
HWY_INLINE ColourLanes blend_over(VF r, VF g, VF b, VF a, hn::Vec<DU> dst) {
    const VF keep = hn::Sub(hn::Set(DF(), 1.0f), a);
    return {hn::Add(hn::Mul(r, a), hn::Mul(unpack_channel(dst, 0), keep)),
            hn::Add(hn::Mul(g, a), hn::Mul(unpack_channel(dst, 8), keep)),
            hn::Add(hn::Mul(b, a), hn::Mul(unpack_channel(dst, 16), keep)), hn::Add(a, hn::Mul(unpack_channel(dst, 24), keep))};
}

// How many varyings' derivatives a shader's lanes read: Lanes::D, or none.
template <class Lanes>
constexpr int derivative_lanes() {
    if constexpr (requires { Lanes::D; }) return Lanes::D;
    else return 0;
}

// Whether a shader's lanes may see zeros of either sign where the specification has one sign
// (Lanes::k_signed_zeros false: every value they compute goes to to_rgba8, which makes -0 and 0 the
// same byte, through operations that keep a zero a zero), and whether they read front_facing.
template <class Lanes>
constexpr bool signed_zeros() {
    if constexpr (requires { Lanes::k_signed_zeros; }) return Lanes::k_signed_zeros;
    else return true;
}
template <class Lanes>
constexpr bool reads_front_facing() {
    if constexpr (requires { Lanes::k_front_facing; }) return Lanes::k_front_facing;
    else return true;
}

// The terms of the planes that depend on a lane's row alone, dq/dy dy, dl1/dy dy and dl2/dy dy
// (dy = centre_y - y0): the same for every block of a row of blocks that one triangle owns.
struct RowTerms {
    VF q, l1, l2;
};
template <class Field>
HWY_INLINE RowTerms row_terms(const Field& field, VF centre_y) {
    const VF dy = hn::Sub(centre_y, field(sh_y0));
    return {hn::Mul(field(sh_dqdy), dy), hn::Mul(field(sh_dl1dy), dy), hn::Mul(field(sh_dl2dy), dy)};
}

// The inputs of the lanes in `active`, whose pixel centres are (centre_x, centre_y) (each x + 0.5
// computed exactly as fragment_at does; the y terms of the planes in `row`, row_terms): interpolation
// (and derivatives) as in fragment_at, with each triangle value read by field(j) (record offset j).
// Without SignedZeros the barycentric sums leave out fragment_at's leading 0 +, which can change
// only the sign of a zero.
template <int N, int D, bool SignedZeros = true, bool FrontFacing = true, class Field>
HWY_INLINE void interpolate_lanes(const Field& field, VF centre_x, const RowTerms& row, MF active, LanesIn<N, D>& in) {
    const DF df;
    const VF dx = hn::Sub(centre_x, field(sh_x0));
    const VF q = hn::Add(hn::Add(field(sh_q0), hn::Mul(field(sh_dqdx), dx)), row.q);
    const VF w = hn::Div(hn::Set(df, 1.0f), q);
    // 0 + ..., as fragment_at: the planes are 0 at (x0, y0), and the sum keeps fragment_at's bits.
    const VF zero = hn::Zero(df);
    auto from_zero = [&](VF v) { return SignedZeros ? hn::Add(zero, v) : v; };
    const VF b1 = hn::Mul(hn::Add(from_zero(hn::Mul(field(sh_dl1dx), dx)), row.l1), w);
    const VF b2 = hn::Mul(hn::Add(from_zero(hn::Mul(field(sh_dl2dx), dx)), row.l2), w);
    for (int k = 0; k < N; ++k)
        in.v[k] = hn::Add(hn::Add(field(k_shading_head + k), hn::Mul(b1, field(k_shading_head + N + k))),
                          hn::Mul(b2, field(k_shading_head + 2 * N + k)));
    if constexpr (D > 0) {
        // d(l/q)/dx = (dl/dx - (l/q) dq/dx) / q, as fragment_at.
        const VF b1x = hn::Mul(hn::Sub(field(sh_dl1dx), hn::Mul(b1, field(sh_dqdx))), w);
        const VF b1y = hn::Mul(hn::Sub(field(sh_dl1dy), hn::Mul(b1, field(sh_dqdy))), w);
        const VF b2x = hn::Mul(hn::Sub(field(sh_dl2dx), hn::Mul(b2, field(sh_dqdx))), w);
        const VF b2y = hn::Mul(hn::Sub(field(sh_dl2dy), hn::Mul(b2, field(sh_dqdy))), w);
        for (int k = 0; k < D; ++k) {
            const VF d1 = field(k_shading_head + N + k), d2 = field(k_shading_head + 2 * N + k);
            in.ddx[k] = hn::Add(hn::Mul(b1x, d1), hn::Mul(b2x, d2));
            in.ddy[k] = hn::Add(hn::Mul(b1y, d1), hn::Mul(b2y, d2));
        }
    }
    if constexpr (FrontFacing) in.front_facing = hn::Gt(field(sh_front), hn::Zero(df));
    in.visible = active;
    in.scalar = hn::FirstN(df, 0);
}

constexpr int k_max_lanes = HWY_MAX_BYTES / sizeof(float);

// Rows of the worker's empty tiles (DeferredFills) written before each block with visible pixels:
// the pass's long chains of arithmetic leave the stores room to drain (the same rows written
// between the triangles of pass one, whose own stores they compete with, cost 2-4% more of a mesh
// frame). Two rows a block (512 bytes at 16 lanes) still clear the empty tiles around the scanned
// meshes at 1920x1080 within their shading, and fewer streaming stores wait on each other than with
// three; one row a block leaves much of the clear to be written alone after the tiles (drain_fills).
constexpr int k_fill_rows_per_block = 2;

// Pixels are shaded in blocks of W x H (4 x 4 with 16 lanes, 4 x 2 with 8, 4 x 1 with 4): the
// pixels of a block belong to fewer triangles than a row of as many pixels (measured on a bunny at
// 1920x1080: 5.9 triangles per 16-pixel row segment), and each triangle in a vector costs one
// broadcast per record value.
constexpr int k_block_w = k_max_lanes < 4 ? k_max_lanes : 4;

// The W x H block of 32-bit values at p (rows `stride` apart) as one vector, row by row.
template <class D, class T>
HWY_INLINE hn::Vec<D> load_block(D d, const T* p, int stride) {
    constexpr std::size_t lanes = hn::MaxLanes(D());
    if constexpr (lanes <= 4) {
        (void)stride;
        return hn::LoadU(d, p);
    } else {
#if HWY_TARGET != HWY_SCALAR  // (one lane: no halves)
        const hn::Half<D> dh;
        constexpr int half_rows = static_cast<int>(lanes) / 2 / k_block_w;
        return hn::Combine(d, load_block(dh, p + half_rows * stride, stride), load_block(dh, p, stride));
#endif
    }
}

template <class D, class T>
HWY_INLINE void store_block(D d, hn::Vec<D> v, T* p, int stride) {
    constexpr std::size_t lanes = hn::MaxLanes(D());
    if constexpr (lanes <= 4) {
        (void)stride;
        hn::StoreU(v, d, p);
    } else {
#if HWY_TARGET != HWY_SCALAR
        const hn::Half<D> dh;
        constexpr int half_rows = static_cast<int>(lanes) / 2 / k_block_w;
        store_block(dh, hn::LowerHalf(dh, v), p, stride);
        store_block(dh, hn::UpperHalf(dh, v), p + half_rows * stride, stride);
#endif
    }
}

// For the lambdas of the shared blocks' blends: GCC otherwise calls some of them, with their
// captures on the stack.
#ifndef FACET_FORCE_INLINE
#define FACET_FORCE_INLINE __attribute__((always_inline))
#endif

// AVX-512 finds a shared block's triangles by conflict detection (ShadeVisibleTile).
#undef FACET_VISIBLE_CONFLICT_LEADERS
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
#define FACET_VISIBLE_CONFLICT_LEADERS 1
// Each lane's bits of the earlier lanes holding the same value (AVX512CD's vpconflictd: Highway has
// no op for it and its AVX3 target does not enable it, so inline assembly, run only where
// cpu_has_conflict_detection).
HWY_INLINE hn::Vec<DU> earlier_equal_lanes(hn::Vec<DU> v) {
    __m512i r;
    __asm__("vpconflictd %1, %0" : "=v"(r) : "v"(v.raw));
    return hn::Vec<DU>{r};
}
// Lane r (< 4) of v, from its low 128 bits (vpextrd: no store and reload).
template <int r>
HWY_INLINE std::uint32_t lane_of(hn::Vec<DU> v) {
    static_assert(r >= 0 && r < 4);
    return static_cast<std::uint32_t>(_mm_extract_epi32(_mm512_castsi512_si128(v.raw), r));
}
#else
#define FACET_VISIBLE_CONFLICT_LEADERS 0
#endif

// GCC 12 cannot see that the runs found from the leaders' bits fill run_record[0, runs) before the
// blends read it, and warns; the entries read are exactly those written.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
template <class S, class Lanes>
void ShadeVisibleTile(const S& shader, const Lanes& lanes_in, const VisibleTile& vis, TargetView target) {
    // A copy of the shader's lanes on the stack, whose address does not escape: the stores to the
    // target cannot alias it, so the compiler keeps its uniforms (and what it computes from them
    // alone) in registers across the blocks instead of loading them again after every store.
    const Lanes lanes = lanes_in;
    constexpr int N = S::k_varyings;
    static_assert(Lanes::N == N);
    const DF df;
    const DU du;
    constexpr int lane_count = static_cast<int>(hn::MaxLanes(DF()));
    constexpr int bw = lane_count < k_block_w ? lane_count : k_block_w, bh = lane_count / bw;
    static_assert(bw * bh == lane_count);
    constexpr std::uint64_t block_row_bits = (1ull << bw) - 1;
    const PixelRect tile = vis.rect;
    const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
    const int simd_width = width / bw * bw, simd_height = height / bh * bh;  // whole blocks inside the tile
    const std::uint64_t tail_bits = simd_width >= 64 ? 0 : ~0ull << simd_width;
    const float* records = vis.records;
    const auto none = hn::Set(du, VisibleTile::k_no_owner);
    constexpr std::uint64_t all_bits = lane_count >= 64 ? ~0ull : (1ull << lane_count) - 1;
    const MF all_lanes = hn::FirstN(df, lane_count);
    // Lane l of a block is pixel (l % bw, l / bw) of it.
    HWY_ALIGN float column[lane_count], row[lane_count];
    for (int l = 0; l < lane_count; ++l) column[l] = static_cast<float>(l % bw), row[l] = static_cast<float>(l / bw);
    const VF lane_column = hn::Load(df, column), lane_row = hn::Load(df, row), half = hn::Set(df, 0.5f);
    // Each lane's neighbours in its block: left, up-left, up, up-right (see the runs below).
    constexpr int k_neighbours = 4;
    using LaneIndices = decltype(hn::SetTableIndices(du, static_cast<const std::int32_t*>(nullptr)));
    LaneIndices neighbour[k_neighbours];
    hn::Mask<DU> has_neighbour[k_neighbours];
    {
        constexpr int step[k_neighbours][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}};  // column, row
        for (int k = 0; k < k_neighbours; ++k) {
            HWY_ALIGN std::int32_t index[lane_count];
            HWY_ALIGN std::uint32_t has[lane_count];
            for (int l = 0; l < lane_count; ++l) {
                const int c = l % bw + step[k][0], r = l / bw + step[k][1];
                const bool inside = c >= 0 && c < bw && r >= 0 && r < bh;
                index[l] = inside ? r * bw + c : l;
                has[l] = inside ? 1u : 0u;
            }
            neighbour[k] = hn::SetTableIndices(du, index);
            has_neighbour[k] = hn::Eq(hn::Load(du, has), hn::Set(du, 1u));
        }
    }
    const int colour_stride = target.stride;
#if FACET_VISIBLE_CONFLICT_LEADERS
    const bool conflict_leaders = cpu_has_conflict_detection();
#endif

    std::uint64_t redo[k_max_tile_size];  // per row: pixels for the specification
    for (int r = 0; r < height; ++r) redo[r] = vis.covered[r] & (r < simd_height ? tail_bits : ~0ull);
    // A row of blocks is shaded in two steps: first each block's triangles are found and its inputs
    // interpolated, then the shader runs on every block of the row. The shader's arithmetic is one
    // long chain of dependent operations per block (a division, a square root and another division
    // in a row for Lambert), whose inputs must be ready when it is issued: a chain issued right after
    // its own block's first step waits on it, and the core could not overlap it across the next
    // blocks' scalar work and branches (the second step's loop below).
    constexpr int D = derivative_lanes<Lanes>();
    constexpr bool Z = signed_zeros<Lanes>(), F = reads_front_facing<Lanes>();
    struct Block {
        LanesIn<N, D> in;
        int i;  // its first column in the tile
    };
    // Step two of a row of blocks runs during step one of the next row with pixels, a block shaded
    // for each block found: its inputs are ready, so the shader's chains (the divider's) overlap the
    // finding's scalar work and branches, which leave the divider idle. Each block's colours and
    // redo bits are its own: the order of the blocks does not change the image.
    Block blocks[2][k_max_tile_size / bw];
    Block* shading = blocks[1];  // the previous row's blocks, shaded from `shaded` up to `to_shade`
    int shaded = 0, to_shade = 0, shading_r0 = 0;
    auto shade_block = [&](Block& block) FACET_FORCE_INLINE {
        LanesIn<N, D>& in = block.in;
        const int i = block.i;
        // A shader's lanes may pack their own colours (e.g. grey ones, once for three channels).
        hn::Vec<DU> rgba;
        if constexpr (requires { lanes.rgba8(in); }) rgba = lanes.rgba8(in);
        else rgba = to_rgba8(lanes(in));
        // Rgba8 is four bytes, r first: stored as 32-bit lanes (Highway stores may alias).
        auto* colour = reinterpret_cast<std::uint32_t*>(target.colour + target.at(tile.x0 + i, tile.y0 + shading_r0));
        // Read the old colours only to keep the pixels of a partly visible block (reading them
        // for every block was measured at 8% of the pass: the framebuffer is not in the caches).
        if (!hn::AllTrue(df, in.visible))
            rgba = hn::IfThenElse(hn::RebindMask(du, in.visible), rgba, load_block(du, colour, colour_stride));
        store_block(du, rgba, colour, colour_stride);
        if (HWY_LIKELY(none_in_both(df, in.scalar, in.visible))) return;
        const MF redo_lanes = hn::And(in.scalar, in.visible);
        const std::uint64_t redo_bits = mask_bits(redo_lanes);
        for (int r = 0; r < bh; ++r) redo[shading_r0 + r] |= ((redo_bits >> (r * bw)) & block_row_bits) << i;
    };
    for (int r0 = 0; r0 < simd_height; r0 += bh) {
        std::uint64_t any = 0;
        for (int r = 0; r < bh; ++r) any |= vis.covered[r0 + r];
        if (!any) continue;
        Block* const row_blocks = shading == blocks[0] ? blocks[1] : blocks[0];
        const int y = tile.y0 + r0;
        const VF centre_y = hn::Add(hn::Add(hn::Set(df, static_cast<float>(y)), lane_row), half);
        // The y terms of the last whole block's triangle in this row of blocks.
        const float* row_record = nullptr;
        RowTerms row{};
        int count = 0;
        for (int i = 0; i < simd_width; i += bw) {
            std::uint64_t bits = 0;
            for (int r = 0; r < bh; ++r) bits |= ((vis.covered[r0 + r] >> i) & block_row_bits) << (r * bw);
            if (!bits) continue;
            if (shaded < to_shade) shade_block(shading[shaded++]);
            const auto owners = load_block(du, vis.owner + r0 * VisibleTile::k_row + i, VisibleTile::k_row);
            const int x = tile.x0 + i;
            const VF centre_x = hn::Add(hn::Add(hn::Set(df, static_cast<float>(x)), lane_column), half);
            // A block whose every pixel one triangle owns (most blocks of large triangles): lane 0
            // names it, and no lane needs a mask.
            if (bits == all_bits) {
                const std::uint32_t owner = hn::GetLane(owners);
                if (owner < vis.count && hn::AllTrue(du, hn::Eq(owners, hn::Set(du, owner)))) {
                    stream_fill_rows(*vis.idle, k_fill_rows_per_block);
                    Block& block = row_blocks[count++];
                    block.i = i;
                    const float* record = records + static_cast<std::size_t>(owner) * vis.record_stride;
                    auto field = [&](int j) { return hn::Set(df, record[j]); };
                    if (record != row_record) row = row_terms(field, centre_y), row_record = record;
                    interpolate_lanes<N, D, Z, F>(field, centre_x, row, all_lanes, block.in);
                    continue;
                }
            }
            std::uint8_t bytes[8];
            std::memcpy(bytes, &bits, sizeof(bytes));
            const MF visible = hn::RebindMask(df, and_compare<Compare::ne>(du, hn::LoadMaskBits(du, bytes), owners, none));
            if (hn::AllFalse(df, visible)) continue;
            stream_fill_rows(*vis.idle, k_fill_rows_per_block);
            // Two to four runs (most shared blocks) with the count known at compile time: the masks
            // and records stay in registers and no field's blend tests the count. Run 0's record is the
            // base the others are blended over where their masks are set.
            auto blend_runs = [&]<int R>(const MF (&mask)[R], const float* const (&record)[R], LanesIn<N, D>& in) FACET_FORCE_INLINE {
                auto field = [&](int j) FACET_FORCE_INLINE {
                    VF v = hn::Set(df, record[0][j]);
                    for (int r = 1; r < R; ++r) v = hn::IfThenElse(mask[r], hn::Set(df, record[r][j]), v);
                    return v;
                };
                interpolate_lanes<N, D, Z, F>(field, centre_x, row_terms(field, centre_y), visible, in);
            };

            // The triangles owning the visible lanes: each lane's value of a record field is
            // assembled from one broadcast per triangle. (Gathering values lane by lane was measured
            // 25% slower over a bunny frame, and several times slower when four triangles share a vector.)
            // A lane's left, up-left, up and up-right neighbours all come before it in the block's row
            // order, so a triangle's first lane has none of them in the same triangle: the lanes
            // without such a neighbour (leaders) name every owner, and their runs are found
            // independently of each other, not one after another by removing each from the rest
            // (that chain was a third of a 4x4 block with four owners). A triangle whose rows in the
            // block do not touch may lead twice; its second run blends the same values again.
#if FACET_VISIBLE_CONFLICT_LEADERS
            // With conflict detection each triangle leads once: its leader is its first visible lane,
            // the one with no earlier lane of the same triangle (invisible lanes are `none` here).
            // The leaders' triangles, packed in lane order (run 0 the first visible lane's, as
            // below), name the runs from registers, with no store and reload per run.
            if (conflict_leaders) {
                const auto owned = hn::IfThenElse(hn::RebindMask(du, visible), owners, none);
                const auto leaders =
                    and_compare<Compare::eq>(du, hn::RebindMask(du, visible), earlier_equal_lanes(owned), hn::Zero(du));
                const int runs = static_cast<int>(hn::CountTrue(du, leaders));
                const auto run_owners = hn::Compress(owned, leaders);
                auto record_of = [&](std::uint32_t owner) FACET_FORCE_INLINE {
                    return records + static_cast<std::size_t>(owner) * vis.record_stride;
                };
                const float* first = record_of(hn::GetLane(run_owners));
                Block& block = row_blocks[count++];
                block.i = i;
                if (runs == 1) {
                    auto field = [&](int j) FACET_FORCE_INLINE { return hn::Set(df, first[j]); };
                    interpolate_lanes<N, D, Z, F>(field, centre_x, row_terms(field, centre_y), visible, block.in);
                } else if (runs <= 4) {
                    auto blend = [&]<int R>() FACET_FORCE_INLINE {
                        MF mask[R];
                        const float* record[R];
                        record[0] = first;
                        auto run = [&]<int r>() FACET_FORCE_INLINE {
                            const std::uint32_t owner = lane_of<r>(run_owners);
                            mask[r] = hn::RebindMask(df, hn::Eq(owned, hn::Set(du, owner)));
                            record[r] = record_of(owner);
                        };
                        run.template operator()<1>();
                        if constexpr (R > 2) run.template operator()<2>();
                        if constexpr (R > 3) run.template operator()<3>();
                        blend_runs(mask, record, block.in);
                    };
                    if (runs == 2) blend.template operator()<2>();
                    else if (runs == 3) blend.template operator()<3>();
                    else blend.template operator()<4>();
                } else {
                    HWY_ALIGN std::uint32_t run_owner[lane_count];
                    hn::Store(run_owners, du, run_owner);
                    MF run_mask[lane_count];
                    const float* run_record[lane_count];
                    for (int r = 1; r < runs; ++r) {
                        run_mask[r] = hn::RebindMask(df, hn::Eq(owned, hn::Set(du, run_owner[r])));
                        run_record[r] = record_of(run_owner[r]);
                    }
                    auto field = [&](int j) FACET_FORCE_INLINE {
                        VF v = hn::Set(df, first[j]);
                        for (int r = 1; r < runs; ++r) v = hn::IfThenElse(run_mask[r], hn::Set(df, run_record[r][j]), v);
                        return v;
                    };
                    interpolate_lanes<N, D, Z, F>(field, centre_x, row_terms(field, centre_y), visible, block.in);
                }
                continue;
            }
#endif
            HWY_ALIGN std::uint32_t owner_of[lane_count];
            hn::Store(owners, du, owner_of);
            MF run_mask[lane_count];
            const float* run_record[lane_count];
            // Run 0 is the first visible lane's triangle (the first leader): its values are the
            // base the other runs are blended over, so it needs no mask. When it owns every
            // visible lane (large triangles) there are no leaders to look for.
            const std::uint32_t first_owner = owner_of[hn::FindFirstTrue(df, visible)];
            run_record[0] = records + static_cast<std::size_t>(first_owner) * vis.record_stride;
            int runs = 1;
            const MF first_run = hn::RebindMask(df, hn::Eq(owners, hn::Set(du, first_owner)));
            if (!hn::AllFalse(df, hn::AndNot(first_run, visible))) {
                auto repeats = hn::FirstN(du, 0);
                for (int k = 0; k < k_neighbours; ++k)
                    repeats = hn::Or(repeats, and_compare<Compare::eq>(du, has_neighbour[k], owners,
                                                                       hn::TableLookupLanes(owners, neighbour[k])));
                std::uint64_t leaders = mask_bits(hn::AndNot(hn::RebindMask(df, repeats), visible));
                for (leaders &= leaders - 1; leaders != 0; leaders &= leaders - 1, ++runs) {
                    const std::uint32_t owner = owner_of[std::countr_zero(leaders)];
                    run_mask[runs] =
                        hn::RebindMask(df, and_compare<Compare::eq>(du, hn::RebindMask(du, visible), owners, hn::Set(du, owner)));
                    run_record[runs] = records + static_cast<std::size_t>(owner) * vis.record_stride;
                }
            }
            Block& block = row_blocks[count++];
            block.i = i;
            if (runs == 1) {  // one triangle: plain broadcasts
                const float* record = run_record[0];
                auto field = [&](int j) { return hn::Set(df, record[j]); };
                interpolate_lanes<N, D, Z, F>(field, centre_x, row_terms(field, centre_y), visible, block.in);
            } else {
                auto blend = [&]<int R>() {
                    MF mask[R];
                    const float* record[R];
                    for (int r = 0; r < R; ++r) mask[r] = run_mask[r], record[r] = run_record[r];
                    blend_runs(mask, record, block.in);
                };
                if (runs == 2) blend.template operator()<2>();
                else if (runs == 3) blend.template operator()<3>();
                else if (runs == 4) blend.template operator()<4>();
                else {
                    auto field = [&](int j) {
                        VF v = hn::Set(df, run_record[0][j]);
                        for (int r = 1; r < runs; ++r) v = hn::IfThenElse(run_mask[r], hn::Set(df, run_record[r][j]), v);
                        return v;
                    };
                    interpolate_lanes<N, D, Z, F>(field, centre_x, row_terms(field, centre_y), visible, block.in);
                }
            }
        }
        while (shaded < to_shade) shade_block(shading[shaded++]);
        shading = row_blocks, shaded = 0, to_shade = count, shading_r0 = r0;
    }
    while (shaded < to_shade) shade_block(shading[shaded++]);
    for (int r = 0; r < height; ++r)
        if (redo[r]) shade_visible_pixels(shader, vis, target, tile.y0 + r, redo[r]);
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // FACET_SHADE_VISIBLE_SIMD_INL_H_ toggle
