// Test support: converting facet math types to and from GLM (the test-only oracle), comparing them
// with float tolerances, and seeded random values.
//
// Tolerances are relative to the size of the values compared: two vectors or matrices match when
// every element differs by at most tol * (largest |element| of either operand). That is the error a
// float computation actually makes (rounding is relative to the terms summed, not to the one small
// entry that cancellation may leave), and it stays meaningful for tiny and huge matrices alike.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <random>
#include <sstream>

#include <glm/glm.hpp>

#include "facet/math/mat.hpp"
#include "facet/math/vec.hpp"

// gtest prints these when an EXPECT_EQ on facet types fails (found by ADL, so in namespace facet).
namespace facet {
inline void PrintTo(const Vec2& v, std::ostream* os) { *os << "(" << v.x << ", " << v.y << ")"; }
inline void PrintTo(const Vec3& v, std::ostream* os) { *os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }
inline void PrintTo(const Vec4& v, std::ostream* os) {
    *os << "(" << v.x << ", " << v.y << ", " << v.z << ", " << v.w << ")";
}
inline void PrintTo(const Mat3& m, std::ostream* os) {
    for (int r = 0; r < 3; ++r) *os << "\n  [" << m(r, 0) << ", " << m(r, 1) << ", " << m(r, 2) << "]";
}
inline void PrintTo(const Mat4& m, std::ostream* os) {
    for (int r = 0; r < 4; ++r)
        *os << "\n  [" << m(r, 0) << ", " << m(r, 1) << ", " << m(r, 2) << ", " << m(r, 3) << "]";
}
}  // namespace facet

namespace facet_test {

// The tolerance used throughout unless a test says why it needs another: a few float ulps of the
// largest value involved.
inline constexpr float k_tol = 1e-5f;

// ---- conversions --------------------------------------------------------------------------------

inline glm::vec2 to_glm(facet::Vec2 v) { return {v.x, v.y}; }
inline glm::vec3 to_glm(facet::Vec3 v) { return {v.x, v.y, v.z}; }
inline glm::vec4 to_glm(facet::Vec4 v) { return {v.x, v.y, v.z, v.w}; }
inline facet::Vec2 from_glm(glm::vec2 v) { return {v.x, v.y}; }
inline facet::Vec3 from_glm(glm::vec3 v) { return {v.x, v.y, v.z}; }
inline facet::Vec4 from_glm(glm::vec4 v) { return {v.x, v.y, v.z, v.w}; }

// Element by element through (row, column) accessors on both sides, so these conversions do not
// assume the two layouts agree (a test checks that separately).
inline glm::mat3 to_glm(const facet::Mat3& m) {
    glm::mat3 g;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) g[c][r] = m(r, c);
    return g;
}
inline glm::mat4 to_glm(const facet::Mat4& m) {
    glm::mat4 g;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) g[c][r] = m(r, c);
    return g;
}
inline facet::Mat3 from_glm(const glm::mat3& g) {
    facet::Mat3 m;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m(r, c) = g[c][r];
    return m;
}
inline facet::Mat4 from_glm(const glm::mat4& g) {
    facet::Mat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m(r, c) = g[c][r];
    return m;
}

// ---- comparisons --------------------------------------------------------------------------------

namespace detail {

template <class A, class B>
::testing::AssertionResult elements_near(const A& a, const B& b, int n, float tol, const char* what,
                                         const std::string& a_text, const std::string& b_text) {
    double largest = 0;
    for (int i = 0; i < n; ++i) {
        if (!std::isfinite(a[i]) || !std::isfinite(b[i]))
            return ::testing::AssertionFailure() << what << " holds a non-finite value:\n  actual   " << a_text
                                                 << "\n  expected " << b_text;
        largest = std::max({largest, std::fabs(double(a[i])), std::fabs(double(b[i]))});
    }
    const double allowed = tol * largest;
    for (int i = 0; i < n; ++i) {
        double diff = std::fabs(double(a[i]) - double(b[i]));
        if (diff > allowed)
            return ::testing::AssertionFailure()
                   << what << " element " << i << " differs by " << diff << " > " << allowed << " (tol " << tol
                   << " x largest " << largest << "):\n  actual   " << a_text << "\n  expected " << b_text;
    }
    return ::testing::AssertionSuccess();
}

template <class T>
std::string print(const T& v) {
    std::ostringstream os;
    facet::PrintTo(v, &os);
    return os.str();
}

// Flat row-major views, element i = (i / N, i % N).
struct Flat4 {
    float v[16];
    float operator[](int i) const { return v[i]; }
};
struct Flat3 {
    float v[9];
    float operator[](int i) const { return v[i]; }
};
inline Flat4 flat(const facet::Mat4& m) {
    Flat4 f;
    for (int i = 0; i < 16; ++i) f.v[i] = m(i / 4, i % 4);
    return f;
}
inline Flat3 flat(const facet::Mat3& m) {
    Flat3 f;
    for (int i = 0; i < 9; ++i) f.v[i] = m(i / 3, i % 3);
    return f;
}

}  // namespace detail

// Usage: EXPECT_TRUE(mat_near(actual, expected)) — the failure message prints both.
inline ::testing::AssertionResult mat_near(const facet::Mat4& a, const facet::Mat4& b, float tol = k_tol) {
    return detail::elements_near(detail::flat(a), detail::flat(b), 16, tol, "Mat4", detail::print(a),
                                 detail::print(b));
}
inline ::testing::AssertionResult mat_near(const facet::Mat4& a, const glm::mat4& b, float tol = k_tol) {
    return mat_near(a, from_glm(b), tol);
}
inline ::testing::AssertionResult mat_near(const facet::Mat3& a, const facet::Mat3& b, float tol = k_tol) {
    return detail::elements_near(detail::flat(a), detail::flat(b), 9, tol, "Mat3", detail::print(a),
                                 detail::print(b));
}
inline ::testing::AssertionResult mat_near(const facet::Mat3& a, const glm::mat3& b, float tol = k_tol) {
    return mat_near(a, from_glm(b), tol);
}

inline ::testing::AssertionResult vec_near(facet::Vec2 a, facet::Vec2 b, float tol = k_tol) {
    return detail::elements_near(a, b, 2, tol, "Vec2", detail::print(a), detail::print(b));
}
inline ::testing::AssertionResult vec_near(facet::Vec3 a, facet::Vec3 b, float tol = k_tol) {
    return detail::elements_near(a, b, 3, tol, "Vec3", detail::print(a), detail::print(b));
}
inline ::testing::AssertionResult vec_near(facet::Vec4 a, facet::Vec4 b, float tol = k_tol) {
    return detail::elements_near(a, b, 4, tol, "Vec4", detail::print(a), detail::print(b));
}
inline ::testing::AssertionResult vec_near(facet::Vec2 a, glm::vec2 b, float tol = k_tol) {
    return vec_near(a, from_glm(b), tol);
}
inline ::testing::AssertionResult vec_near(facet::Vec3 a, glm::vec3 b, float tol = k_tol) {
    return vec_near(a, from_glm(b), tol);
}
inline ::testing::AssertionResult vec_near(facet::Vec4 a, glm::vec4 b, float tol = k_tol) {
    return vec_near(a, from_glm(b), tol);
}

// Scalars: |a - b| <= tol * max(|a|, |b|, scale). `scale` is the size of the terms that produced the
// values (pass it when the result may be a small difference of large terms).
inline ::testing::AssertionResult float_near(double a, double b, double tol = k_tol, double scale = 0) {
    double allowed = tol * std::max({std::fabs(a), std::fabs(b), scale});
    if (std::isfinite(a) && std::isfinite(b) && std::fabs(a - b) <= allowed) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " vs " << b << ": differ by " << std::fabs(a - b) << " > " << allowed;
}

template <class M>
bool all_finite(const M& m) {
    for (const auto& c : m.col)
        if (!facet::is_finite(c)) return false;
    return true;
}

// ---- random values ------------------------------------------------------------------------------

// A seeded generator: every run draws the same values, so a failure reproduces.
class Rng {
public:
    explicit Rng(unsigned seed) : gen_(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen_); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(gen_); }
    float sign() { return integer(0, 1) ? 1.0f : -1.0f; }
    facet::Vec2 vec2(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi)}; }
    facet::Vec3 vec3(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    facet::Vec4 vec4(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    // A direction uniformly distributed on the unit sphere.
    facet::Vec3 unit3() {
        for (;;) {
            facet::Vec3 v = vec3(-1, 1);
            float l2 = facet::dot(v, v);
            if (l2 > 1e-4f && l2 <= 1) return v / std::sqrt(l2);
        }
    }
    facet::Mat3 mat3(float lo, float hi) {
        facet::Mat3 m;
        for (auto& c : m.col) c = vec3(lo, hi);
        return m;
    }
    facet::Mat4 mat4(float lo, float hi) {
        facet::Mat4 m;
        for (auto& c : m.col) c = vec4(lo, hi);
        return m;
    }

private:
    std::mt19937 gen_;
};

}  // namespace facet_test
