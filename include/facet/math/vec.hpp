// facet math: small fixed-size float vectors (Vec2, Vec3, Vec4) with GLSL-style free functions.
// Plain aggregates, no SIMD inside: the pipeline's hot loops work on arrays, not on these.
#pragma once

#include <cmath>
#include <cstddef>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet {

struct Vec2 {
    float x = 0, y = 0;
    constexpr float& operator[](std::size_t i) { return (&x)[i]; }
    constexpr float operator[](std::size_t i) const { return (&x)[i]; }
};

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr float& operator[](std::size_t i) { return (&x)[i]; }
    constexpr float operator[](std::size_t i) const { return (&x)[i]; }
};

struct Vec4 {
    float x = 0, y = 0, z = 0, w = 0;
    constexpr Vec4() = default;
    constexpr Vec4(float x_, float y_, float z_, float w_) : x(x_), y(y_), z(z_), w(w_) {}
    constexpr Vec4(Vec3 v, float w_) : x(v.x), y(v.y), z(v.z), w(w_) {}
    constexpr float& operator[](std::size_t i) { return (&x)[i]; }
    constexpr float operator[](std::size_t i) const { return (&x)[i]; }
    constexpr Vec3 xyz() const { return {x, y, z}; }
};

// Component-wise arithmetic, generated once for the three sizes.
#define FACET_VEC_OPS(V, N)                                                                      \
    constexpr V operator+(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] + b[i]; return r; } \
    constexpr V operator-(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] - b[i]; return r; } \
    constexpr V operator*(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] * b[i]; return r; } \
    constexpr V operator/(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] / b[i]; return r; } \
    constexpr V operator*(V a, float s) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] * s; return r; } \
    constexpr V operator*(float s, V a) { return a * s; }                                        \
    constexpr V operator/(V a, float s) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] / s; return r; } \
    constexpr V operator-(V a) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = -a[i]; return r; } \
    constexpr V& operator+=(V& a, V b) { return a = a + b; }                                     \
    constexpr V& operator-=(V& a, V b) { return a = a - b; }                                     \
    constexpr V& operator*=(V& a, float s) { return a = a * s; }                                 \
    constexpr bool operator==(V a, V b) { for (std::size_t i = 0; i < N; ++i) if (a[i] != b[i]) return false; return true; } \
    constexpr float dot(V a, V b) { float s = 0; for (std::size_t i = 0; i < N; ++i) s += a[i] * b[i]; return s; } \
    inline float length(V a) { return std::sqrt(dot(a, a)); }                                    \
    inline bool is_finite(V a) { for (std::size_t i = 0; i < N; ++i) if (!std::isfinite(a[i])) return false; return true; }    \
    /* The zero vector and non-finite input normalize to the zero vector, never to NaN: callers */ \
    /* that need a fallback direction check the result. Vectors so long that their squared */      \
    /* length overflows (components past ~1e19) are scaled down first, so they keep their direction. */ \
    /* The rare cases live out of line so that the common one inlines into pixel loops. */     \
    [[gnu::noinline, gnu::cold]] inline V normalize_rare(V a) {                                  \
        if (!is_finite(a)) return V{};                                                           \
        float m = 0;                                                                             \
        for (std::size_t i = 0; i < N; ++i) m = std::fmax(m, std::fabs(a[i]));                   \
        if (!(m > 0)) return V{};                                                                \
        const V b = a / m;                                                                       \
        return b / length(b);                                                                    \
    }                                                                                            \
    inline V normalize(V a) {                                                                    \
        const float l = length(a);                                                               \
        if (l > 0 && std::isfinite(l)) [[likely]] return a / l;                                  \
        return normalize_rare(a);                                                                \
    }                                                                                            \
    constexpr V min(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] < b[i] ? a[i] : b[i]; return r; } \
    constexpr V max(V a, V b) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] > b[i] ? a[i] : b[i]; return r; } \
    constexpr V mix(V a, V b, float t) { return a + (b - a) * t; }                               \
    constexpr V clamp(V a, float lo, float hi) { V r; for (std::size_t i = 0; i < N; ++i) r[i] = a[i] < lo ? lo : (a[i] > hi ? hi : a[i]); return r; } 

FACET_VEC_OPS(Vec2, 2)
FACET_VEC_OPS(Vec3, 3)
FACET_VEC_OPS(Vec4, 4)
#undef FACET_VEC_OPS

constexpr Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

constexpr float clamp(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }
constexpr float mix(float a, float b, float t) { return a + (b - a) * t; }

constexpr float k_pi = 3.14159265358979323846f;
constexpr float radians(float degrees) { return degrees * (k_pi / 180.0f); }
constexpr float degrees(float radians) { return radians * (180.0f / k_pi); }

}  // namespace facet
FACET_API_END
