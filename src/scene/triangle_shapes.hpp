// facet scene internals: face normals and the corner angles of many triangles at once
// (triangle_shapes_simd.cpp), for compute_creased_normals (creased_normals.cpp), whose
// describe_triangle is the specification, with corner_acos for the angles.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace facet::detail {

// The arc cosine of the corner angles: fdlibm's acosf (e_acosf.c), as glibc 2.36's libm computes
// it: the same bits as std::acos(float) there for every float in [-1, 1] (checked exhaustively, all
// 2,130,706,434 of them), so normals are what they were with std::acos, and the kernel's lanes
// (the same operations) give the same bits on every ISA and with any libm. Only float +, -, *, /
// and sqrt, each correctly rounded (no FMA: -ffp-contract=off).
namespace acos_terms {
inline constexpr float pi = std::bit_cast<float>(0x40490fdau), pio2_hi = std::bit_cast<float>(0x3fc90fdau),
                   pio2_lo = std::bit_cast<float>(0x33a22168u);
inline constexpr float p[6] = {std::bit_cast<float>(0x3e2aaaabu), std::bit_cast<float>(0xbea6b090u),
                           std::bit_cast<float>(0x3e4e0aa8u), std::bit_cast<float>(0xbd241146u),
                           std::bit_cast<float>(0x3a4f7f04u), std::bit_cast<float>(0x3811ef08u)};
inline constexpr float q[4] = {std::bit_cast<float>(0xc019d139u), std::bit_cast<float>(0x4001572du),
                           std::bit_cast<float>(0xbf303361u), std::bit_cast<float>(0x3d9dc62eu)};
// p(z) / q(z), the rational approximation of the series' tail.
inline float rational(float z) {
    const float num = z * (p[0] + z * (p[1] + z * (p[2] + z * (p[3] + z * (p[4] + z * p[5])))));
    const float den = 1.0f + z * (q[0] + z * (q[1] + z * (q[2] + z * q[3])));
    return num / den;
}
}  // namespace acos_terms

inline float corner_acos(float x) {
    using namespace acos_terms;
    const std::uint32_t hx = std::bit_cast<std::uint32_t>(x), ix = hx & 0x7fffffffu;
    if (ix == 0x3f800000u) return hx >> 31 ? pi + 2.0f * pio2_lo : 0.0f;  // |x| == 1
    if (ix > 0x3f800000u) return (x - x) / (x - x);                       // NaN, |x| > 1
    if (ix < 0x3f000000u) {                                               // |x| < 0.5
        if (ix <= 0x32800000u) return pio2_hi + pio2_lo;
        return pio2_hi - (x - (pio2_lo - x * rational(x * x)));
    }
    const float z = (1.0f - std::fabs(x)) * 0.5f;  // 1 + x for x < 0: the same rounding
    const float s = std::sqrt(z), r = rational(z);
    if (hx >> 31) return pi - 2.0f * (s + (r * s - pio2_lo));
    const float df = std::bit_cast<float>(std::bit_cast<std::uint32_t>(s) & 0xfffff000u);
    const float c = (z - df * df) / (s + df);
    return 2.0f * (df + (r * s + c));
}

// k_capacity triangles as structures of arrays: their corners' positions in, their shapes out.
struct TriangleChunk {
    static constexpr std::size_t k_capacity = 64;  // a bit of `unusual` each
    alignas(64) float corner[3][3][k_capacity];    // [corner][axis][triangle]
    alignas(64) float face[3][k_capacity];         // the normal, [axis][triangle]
    alignas(64) float cosine[3][k_capacity];       // each corner's, clamped to [-1, 1]
    alignas(64) float angle[3][k_capacity];        // corner_acos of the cosine
    // A bit per triangle left to the specification: one of its four normalizations (the face's and
    // its sides') is not of a vector of finite, non-zero length, so it takes normalize's rare path.
    // Degenerate triangles are among them. The other triangles' face and cosines are the
    // specification's, bit for bit.
    std::uint64_t unusual;
};

// The shapes of all the chunk's triangles (fill the places not used, e.g. with zeros). Returns
// false, computing nothing, when the scalar ISA is selected (facet/isa.hpp).
bool shape_triangles(TriangleChunk& chunk);

// corner_acos of each of the n values in place, in the kernel's lanes (for the tests). Returns false,
// computing nothing, when the scalar ISA is selected.
bool corner_acos_lanes(float* values, std::size_t n);

}  // namespace facet::detail
