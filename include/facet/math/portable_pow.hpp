// facet math: x^y and log2 x with the same bits on every machine and in every SIMD lane.
// std::pow and std::log2 come from the C library, which picks its implementation by CPU (glibc: an FMA version or
// not) and differs between library versions; a shader that calls it can give different images on
// different machines, and it has no vector form that matches it bit for bit. portable_pow is built
// from float additions, multiplications, one division and exact bit manipulations only, in a fixed
// order, so the SIMD shading kernels (src/shade/visible_simd-inl.h) reproduce it exactly.
// Accuracy (against std::pow in double): relative error below 2e-6 when |y log2 x| < 16, below 1e-5
// up to 128 (the rounding of y log2 x to float alone costs that much there); results below 2^-126
// are 0, above 2^128 infinite. For shading, where results are at most 1, that is far below 1/255.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet {

namespace detail {
// log2(m) for m in [sqrt(1/2), sqrt(2)): 2/ln 2 atanh(t), t = (m - 1) / (m + 1), |t| <= 0.1716.
constexpr float k_log2_c1 = 2.8853900817779268f;    // 2 / ln 2
constexpr float k_log2_c3 = 0.96179669392597560f;   // 2 / (3 ln 2)
constexpr float k_log2_c5 = 0.57707801635558536f;   // 2 / (5 ln 2)
constexpr float k_log2_c7 = 0.41219858311113240f;   // 2 / (7 ln 2)
constexpr float k_log2_c9 = 0.32059889797532520f;   // 2 / (9 ln 2)
// 2^f for f in [-1/2, 1/2]: Taylor series of e^(f ln 2) to degree 7.
constexpr float k_exp2_c1 = 0.69314718055994531f;
constexpr float k_exp2_c2 = 0.24022650695910071f;
constexpr float k_exp2_c3 = 0.055504108664821580f;
constexpr float k_exp2_c4 = 0.0096181291076284772f;
constexpr float k_exp2_c5 = 0.0013333558146428443f;
constexpr float k_exp2_c6 = 0.00015403530393381609f;
constexpr float k_exp2_c7 = 0.000015252733804059841f;
constexpr float k_sqrt2 = 1.41421356237309505f;

// log2 of a positive normal float.
inline float portable_log2(float x) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    float e = static_cast<float>(static_cast<std::int32_t>(bits >> 23) - 127);
    float m = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // [1, 2)
    if (m > k_sqrt2) {
        m = m * 0.5f;
        e = e + 1.0f;
    }
    const float t = (m - 1.0f) / (m + 1.0f);
    const float t2 = t * t;
    const float p = k_log2_c1 + t2 * (k_log2_c3 + t2 * (k_log2_c5 + t2 * (k_log2_c7 + t2 * k_log2_c9)));
    return e + t * p;
}

// 2^z for z in [-126, 128).
inline float portable_exp2(float z) {
    const float i = std::nearbyint(z);
    const float f = z - i;
    const float p =
        1.0f +
        f * (k_exp2_c1 +
             f * (k_exp2_c2 + f * (k_exp2_c3 + f * (k_exp2_c4 + f * (k_exp2_c5 + f * (k_exp2_c6 + f * k_exp2_c7))))));
    // 2^i in two halves, so that i = 128 (z just below 128, rounded up) stays representable.
    const auto n = static_cast<std::int32_t>(i);
    const std::int32_t half = n >> 1;  // floor(n / 2)
    const float s1 = std::bit_cast<float>(static_cast<std::uint32_t>(half + 127) << 23);
    const float s2 = std::bit_cast<float>(static_cast<std::uint32_t>(n - half + 127) << 23);
    return p * s1 * s2;
}
}  // namespace detail

// log2 x: exact at powers of two, within 3.01 units in the last place of the exact result elsewhere
// (checked over every positive float; the worst are near x = 1.09, where the result is small);
// log2 0 = -infinity, log2 infinity = infinity, NaN for x < 0 or NaN. Subnormal x is scaled into the
// normal range exactly, the scale taken back out.
inline float portable_log2(float x) {
    if (!(x > 0.0f)) return x == 0.0f ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::quiet_NaN();
    if (x == std::numeric_limits<float>::infinity()) return x;
    if (x < 0x1p-126f) return detail::portable_log2(x * 0x1p23f) - 23.0f;
    return detail::portable_log2(x);
}

// x^y for x >= 0 (NaN for x < 0 or NaN). x^0 = 1; 0^y = 0 for y > 0, infinity for y < 0.
inline float portable_pow(float x, float y) {
    if (y == 0.0f) return 1.0f;
    if (!(x >= 0.0f)) return std::numeric_limits<float>::quiet_NaN();
    if (x == 0.0f) return y > 0.0f ? 0.0f : std::numeric_limits<float>::infinity();
    if (x == std::numeric_limits<float>::infinity()) return y > 0.0f ? x : 0.0f;
    // Subnormal x: scaled into the normal range exactly, the scale taken back out of the logarithm.
    float bias = 0.0f;
    if (x < 0x1p-126f) {
        x = x * 0x1p23f;
        bias = 23.0f;
    }
    const float z = y * (detail::portable_log2(x) - bias);
    if (!(z < 128.0f)) return z != z ? z : std::numeric_limits<float>::infinity();
    if (z < -126.0f) return 0.0f;
    return detail::portable_exp2(z);
}

}  // namespace facet
FACET_API_END
