// facet vertex: the vertex stage's transforms (detail/vertex_stage.hpp) as SIMD kernels, compiled per
// ISA by Highway and dispatched at run time. One lane per vertex computes what Mat4's and Mat3's
// operator* compute for one: each row as ((c0 x + c1 y) + c2 z) (+ c3 w), the same float operations
// in the same order (no FMA: the project builds with -ffp-contract=off, and Highway's Mul and Add
// round separately), so every ISA writes the bytes of the scalar code.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "vertex/transform_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstring>

#include "facet/detail/vertex_stage.hpp"

#ifndef FACET_VERTEX_TRANSFORM_SIMD_ONCE
#define FACET_VERTEX_TRANSFORM_SIMD_ONCE
namespace facet::detail {

// The scalar code the kernels match, for vertices [first, n): the "scalar" ISA and the kernels' tails.
inline void transform_points_from(std::size_t first, const Mat4& m, const Vec3* points, std::size_t n, Vec4* out) {
    for (std::size_t i = first; i < n; ++i) out[i] = m * Vec4(points[i], 1);
}
inline void transform_directions_from(std::size_t first, const Mat3& m, const Vec3* directions, std::size_t n,
                                      float* out, std::size_t stride) {
    for (std::size_t i = first; i < n; ++i) {
        const Vec3 v = m * directions[i];
        std::memcpy(out + i * stride, &v, sizeof(v));
    }
}

}  // namespace facet::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Vec4) == 4 * sizeof(float), "packed vectors");

// Each element of a matrix (Mat4 or Mat3) broadcast: c[column][row].
template <int Size, class Matrix, class VF>
HWY_INLINE void broadcast_elements(const Matrix& m, VF (&c)[Size][Size]) {
    const hn::ScalableTag<float> df;
    for (int col = 0; col < Size; ++col)
        for (int row = 0; row < Size; ++row) c[col][row] = hn::Set(df, m.col[col][static_cast<std::size_t>(row)]);
}

void TransformPoints(const Mat4& m, const Vec3* points, std::size_t n, Vec4* out) {
    const hn::ScalableTag<float> df;
    using VF = hn::Vec<decltype(df)>;
    const std::size_t lanes = hn::Lanes(df);
    VF c[4][4];
    broadcast_elements<4>(m, c);
    const VF one = hn::Set(df, 1.0f);
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        VF x, y, z;
        hn::LoadInterleaved3(df, reinterpret_cast<const float*>(points + i), x, y, z);
        VF r[4];
        for (int row = 0; row < 4; ++row)
            r[row] = hn::Add(hn::Add(hn::Add(hn::Mul(c[0][row], x), hn::Mul(c[1][row], y)), hn::Mul(c[2][row], z)),
                             hn::Mul(c[3][row], one));
        hn::StoreInterleaved4(r[0], r[1], r[2], r[3], df, reinterpret_cast<float*>(out + i));
    }
    transform_points_from(i, m, points, n, out);
}

void TransformDirections(const Mat3& m, const Vec3* directions, std::size_t n, float* out, std::size_t stride) {
    const hn::ScalableTag<float> df;
    using VF = hn::Vec<decltype(df)>;
    const std::size_t lanes = hn::Lanes(df);
    VF c[3][3];
    broadcast_elements<3>(m, c);
    // Where out is not packed (other varyings follow each normal), the lanes' results go through
    // a packed block and are copied into place.
    HWY_ALIGN float packed[3 * HWY_MAX_BYTES / sizeof(float)];
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        VF x, y, z;
        hn::LoadInterleaved3(df, reinterpret_cast<const float*>(directions + i), x, y, z);
        VF r[3];
        for (int row = 0; row < 3; ++row)
            r[row] = hn::Add(hn::Add(hn::Mul(c[0][row], x), hn::Mul(c[1][row], y)), hn::Mul(c[2][row], z));
        if (stride == 3) {
            hn::StoreInterleaved3(r[0], r[1], r[2], df, out + i * 3);
            continue;
        }
        hn::StoreInterleaved3(r[0], r[1], r[2], df, packed);
        for (std::size_t k = 0; k < lanes; ++k) std::memcpy(out + (i + k) * stride, packed + 3 * k, 3 * sizeof(float));
    }
    transform_directions_from(i, m, directions, n, out, stride);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(TransformPoints);
HWY_EXPORT(TransformDirections);

void transform_points(const Mat4& m, const Vec3* points, std::size_t n, Vec4* out) {
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(TransformPoints)(m, points, n, out);
    transform_points_from(0, m, points, n, out);
}

void transform_directions(const Mat3& m, const Vec3* directions, std::size_t n, float* out, std::size_t stride) {
    if (directions == nullptr) {
        for (std::size_t i = 0; i < n; ++i) std::memset(out + i * stride, 0, 3 * sizeof(float));
        return;
    }
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(TransformDirections)(m, directions, n, out, stride);
    transform_directions_from(0, m, directions, n, out, stride);
}

}  // namespace facet::detail
#endif
