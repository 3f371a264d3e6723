// facet scene: face normals and corner angles of a chunk of triangles (triangle_shapes.hpp) as a
// SIMD kernel, compiled per ISA by Highway and dispatched at run time. One lane per triangle does
// what describe_triangle (creased_normals.cpp, the specification) does: the same float
// operations in the same order (no FMA: -ffp-contract=off, and Highway's Mul, Add and Sub round
// separately; Div and Sqrt are correctly rounded, as their scalar counterparts), dot products
// starting from +0 as facet's dot does, so the lanes give the specification's bits. Lanes where a
// normalization would leave normalize's common path are only flagged: the caller runs the
// specification on those triangles.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "scene/triangle_shapes_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <limits>

#include "scene/triangle_shapes.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class V>
struct Vec3Lanes {
    V x, y, z;
};

// facet's dot: ((0 + x) + y) + z.
template <class D, class V>
HWY_INLINE V DotLanes(D d, const Vec3Lanes<V>& a, const Vec3Lanes<V>& b) {
    return hn::Add(hn::Add(hn::Add(hn::Zero(d), hn::Mul(a.x, b.x)), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}

template <class V>
HWY_INLINE Vec3Lanes<V> SubLanes(const Vec3Lanes<V>& a, const Vec3Lanes<V>& b) {
    return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
}

// normalize's common path; `usual` loses the lanes that would take its rare one.
template <class D, class V, class M>
HWY_INLINE Vec3Lanes<V> NormalizeLanes(D d, const Vec3Lanes<V>& a, M& usual) {
    const V length = hn::Sqrt(DotLanes(d, a, a));
    usual = hn::And(usual, hn::And(hn::Gt(length, hn::Zero(d)),
                                   hn::Lt(length, hn::Set(d, std::numeric_limits<float>::infinity()))));
    return {hn::Div(a.x, length), hn::Div(a.y, length), hn::Div(a.z, length)};
}

// corner_acos in lanes: its three ways all computed and the lanes' own chosen, with the same
// operations in the same order.
template <class D, class V>
HWY_INLINE V AcosLanes(D d, V x) {
    namespace t = acos_terms;
    const hn::RebindToSigned<D> di;
    auto rational = [&](V z) {
        V num = hn::Mul(z, hn::Set(d, t::p[5]));
        for (int k = 4; k >= 0; --k) num = hn::Mul(z, hn::Add(hn::Set(d, t::p[k]), num));
        V den = hn::Mul(z, hn::Set(d, t::q[3]));
        for (int k = 2; k >= 0; --k) den = hn::Mul(z, hn::Add(hn::Set(d, t::q[k]), den));
        return hn::Div(num, hn::Add(hn::Set(d, 1.0f), den));
    };
    const auto hx = hn::BitCast(di, x);
    const auto ix = hn::And(hx, hn::Set(di, 0x7fffffff));
    const auto negative = hn::RebindMask(d, hn::Lt(hx, hn::Zero(di)));
    // |x| < 0.5
    const V small = hn::Sub(hn::Set(d, t::pio2_hi),
                            hn::Sub(x, hn::Sub(hn::Set(d, t::pio2_lo), hn::Mul(x, rational(hn::Mul(x, x))))));
    // |x| >= 0.5
    const V z = hn::Mul(hn::Sub(hn::Set(d, 1.0f), hn::Abs(x)), hn::Set(d, 0.5f));
    const V s = hn::Sqrt(z), rs = hn::Mul(rational(z), s);
    const V below = hn::Sub(hn::Set(d, t::pi), hn::Mul(hn::Set(d, 2.0f), hn::Add(s, hn::Sub(rs, hn::Set(d, t::pio2_lo)))));
    const V df = hn::BitCast(d, hn::And(hn::BitCast(di, s), hn::Set(di, static_cast<std::int32_t>(0xfffff000u))));
    const V c = hn::Div(hn::Sub(z, hn::Mul(df, df)), hn::Add(s, df));
    const V above = hn::Mul(hn::Set(d, 2.0f), hn::Add(df, hn::Add(rs, c)));
    V out = hn::IfThenElse(negative, below, above);
    out = hn::IfThenElse(hn::RebindMask(d, hn::Lt(ix, hn::Set(di, 0x3f000000))), small, out);
    out = hn::IfThenElse(hn::RebindMask(d, hn::Lt(ix, hn::Set(di, 0x32800001))), hn::Set(d, t::pio2_hi + t::pio2_lo), out);
    const V at_one = hn::IfThenElse(negative, hn::Set(d, t::pi + 2.0f * t::pio2_lo), hn::Zero(d));
    out = hn::IfThenElse(hn::RebindMask(d, hn::Eq(ix, hn::Set(di, 0x3f800000))), at_one, out);
    return hn::IfThenElse(hn::RebindMask(d, hn::Gt(ix, hn::Set(di, 0x3f800000))), hn::Div(hn::Sub(x, x), hn::Sub(x, x)), out);
}

void AcosInPlace(float* values, std::size_t n) {
    const hn::ScalableTag<float> d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) hn::StoreU(AcosLanes(d, hn::LoadU(d, values + i)), d, values + i);
    if (i < n) {
        HWY_ALIGN float rest[HWY_MAX_BYTES / sizeof(float)] = {};
        std::copy(values + i, values + n, rest);
        hn::Store(AcosLanes(d, hn::Load(d, rest)), d, rest);
        std::copy(rest, rest + (n - i), values + i);
    }
}

void ShapeTriangles(TriangleChunk& chunk) {
    const hn::ScalableTag<float> d;
    using V = hn::Vec<decltype(d)>;
    const std::size_t lanes = hn::Lanes(d);
    const V minus_one = hn::Set(d, -1.0f), one = hn::Set(d, 1.0f);
    chunk.unusual = 0;
    for (std::size_t i = 0; i < TriangleChunk::k_capacity; i += lanes) {
        Vec3Lanes<V> p[3];
        for (int k = 0; k < 3; ++k)
            p[k] = {hn::Load(d, chunk.corner[k][0] + i), hn::Load(d, chunk.corner[k][1] + i),
                    hn::Load(d, chunk.corner[k][2] + i)};
        auto usual = hn::FirstN(d, lanes);
        const Vec3Lanes<V> a = SubLanes(p[1], p[0]), b = SubLanes(p[2], p[0]);
        const Vec3Lanes<V> cross = {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(a.z, b.y)),
                                    hn::Sub(hn::Mul(a.z, b.x), hn::Mul(a.x, b.z)),
                                    hn::Sub(hn::Mul(a.x, b.y), hn::Mul(a.y, b.x))};
        const Vec3Lanes<V> face = NormalizeLanes(d, cross, usual);
        const Vec3Lanes<V> side[3] = {NormalizeLanes(d, a, usual), NormalizeLanes(d, SubLanes(p[2], p[1]), usual),
                                      NormalizeLanes(d, SubLanes(p[0], p[2]), usual)};
        hn::Store(face.x, d, chunk.face[0] + i);
        hn::Store(face.y, d, chunk.face[1] + i);
        hn::Store(face.z, d, chunk.face[2] + i);
        for (int k = 0; k < 3; ++k) {
            const Vec3Lanes<V>& s = side[(k + 2) % 3];
            const V cosine = DotLanes(d, side[k], Vec3Lanes<V>{hn::Neg(s.x), hn::Neg(s.y), hn::Neg(s.z)});
            // facet's clamp: v < lo ? lo : (v > hi ? hi : v)
            const V clamped = hn::IfThenElse(hn::Lt(cosine, minus_one), minus_one, hn::IfThenElse(hn::Gt(cosine, one), one, cosine));
            hn::Store(clamped, d, chunk.cosine[k] + i);
            hn::Store(AcosLanes(d, clamped), d, chunk.angle[k] + i);
        }
        if (!hn::AllTrue(d, usual)) {
            std::uint8_t bits[8] = {};  // lane j: bit j % 8 of byte j / 8
            hn::StoreMaskBits(d, hn::Not(usual), bits);
            std::uint64_t lane_bits = 0;
            for (std::size_t byte = 0; byte < (lanes + 7) / 8; ++byte)
                lane_bits |= std::uint64_t{bits[byte]} << 8 * byte;
            if (lanes < 64) lane_bits &= (std::uint64_t{1} << lanes) - 1;
            chunk.unusual |= lane_bits << i;
        }
    }
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(ShapeTriangles);
HWY_EXPORT(AcosInPlace);

bool shape_triangles(TriangleChunk& chunk) {
    if (use_scalar_kernels()) return false;
    HWY_DYNAMIC_DISPATCH(ShapeTriangles)(chunk);
    return true;
}

bool corner_acos_lanes(float* values, std::size_t n) {
    if (use_scalar_kernels()) return false;
    HWY_DYNAMIC_DISPATCH(AcosInPlace)(values, n);
    return true;
}

}  // namespace facet::detail
#endif
