// Vec2 / Vec3 / Vec4: arithmetic, dot, cross, length, normalize, min/max/mix/clamp, against GLM and
// hand-derived values.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "facet/math/vec.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::float_near;
using facet_test::from_glm;
using facet_test::Rng;
using facet_test::to_glm;
using facet_test::vec_near;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

// ---- the three sizes, tested by one set of typed tests -------------------------------------------

template <class V>
struct VecTraits;
template <>
struct VecTraits<Vec2> {
    static constexpr int n = 2;
    static Vec2 random(Rng& r, float lo, float hi) { return r.vec2(lo, hi); }
};
template <>
struct VecTraits<Vec3> {
    static constexpr int n = 3;
    static Vec3 random(Rng& r, float lo, float hi) { return r.vec3(lo, hi); }
};
template <>
struct VecTraits<Vec4> {
    static constexpr int n = 4;
    static Vec4 random(Rng& r, float lo, float hi) { return r.vec4(lo, hi); }
};

// A vector with every component set to v (Vec4 has a constructor, Vec2/Vec3 are aggregates).
template <class V>
V splat(float v) {
    V r;
    for (int i = 0; i < VecTraits<V>::n; ++i) r[static_cast<std::size_t>(i)] = v;
    return r;
}

template <class V>
class VecTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec2, Vec3, Vec4>;
TYPED_TEST_SUITE(VecTest, VecTypes);

TYPED_TEST(VecTest, DefaultIsZeroAndIndexingReachesTheNamedComponents) {
    using V = TypeParam;
    constexpr int n = VecTraits<V>::n;
    V v;
    for (int i = 0; i < n; ++i) EXPECT_EQ(v[static_cast<std::size_t>(i)], 0.0f);
    for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = float(10 * (i + 1));
    EXPECT_EQ(v.x, 10.0f);
    EXPECT_EQ(v.y, 20.0f);
    if constexpr (n >= 3) {
        EXPECT_EQ(v.z, 30.0f);
    }
    if constexpr (n >= 4) {
        EXPECT_EQ(v.w, 40.0f);
    }
}

// Each component-wise operation is one IEEE operation per component, so facet and GLM must agree
// exactly (the build has -ffp-contract=off, so nothing is fused).
TYPED_TEST(VecTest, ComponentWiseArithmeticMatchesGlmExactly) {
    using V = TypeParam;
    Rng rng(101);
    for (int it = 0; it < 500; ++it) {
        V a = VecTraits<V>::random(rng, -100, 100);
        V b = VecTraits<V>::random(rng, -100, 100);
        float s = rng.uniform(0.5f, 4.0f) * rng.sign();
        // Keep divisors away from zero.
        for (int i = 0; i < VecTraits<V>::n; ++i)
            if (std::fabs(b[static_cast<std::size_t>(i)]) < 0.5f) b[static_cast<std::size_t>(i)] = 0.5f;
        auto ga = to_glm(a), gb = to_glm(b);
        EXPECT_EQ(a + b, from_glm(ga + gb));
        EXPECT_EQ(a - b, from_glm(ga - gb));
        EXPECT_EQ(a * b, from_glm(ga * gb));
        EXPECT_EQ(a / b, from_glm(ga / gb));
        EXPECT_EQ(a * s, from_glm(ga * s));
        EXPECT_EQ(s * a, from_glm(s * ga));
        EXPECT_EQ(a / s, from_glm(ga / s));
        EXPECT_EQ(-a, from_glm(-ga));
        V c = a;
        c += b;
        EXPECT_EQ(c, a + b);
        c = a;
        c -= b;
        EXPECT_EQ(c, a - b);
        c = a;
        c *= s;
        EXPECT_EQ(c, a * s);
        EXPECT_EQ(min(a, b), from_glm(glm::min(ga, gb)));
        EXPECT_EQ(max(a, b), from_glm(glm::max(ga, gb)));
    }
}

TYPED_TEST(VecTest, EqualityComparesEveryComponent) {
    using V = TypeParam;
    V a = splat<V>(1.0f);
    EXPECT_TRUE(a == splat<V>(1.0f));
    for (int i = 0; i < VecTraits<V>::n; ++i) {
        V b = a;
        b[static_cast<std::size_t>(i)] = 2.0f;
        EXPECT_FALSE(a == b) << "component " << i;
    }
}

TYPED_TEST(VecTest, DotAndLengthMatchGlm) {
    using V = TypeParam;
    Rng rng(102);
    for (int it = 0; it < 500; ++it) {
        V a = VecTraits<V>::random(rng, -10, 10);
        V b = VecTraits<V>::random(rng, -10, 10);
        // Scale of the products summed: the dot product may cancel to a small value.
        float terms = dot(a * a, splat<V>(1.0f)) + dot(b * b, splat<V>(1.0f));
        EXPECT_TRUE(float_near(dot(a, b), glm::dot(to_glm(a), to_glm(b)), 1e-6, terms));
        EXPECT_TRUE(float_near(dot(a, b), dot(b, a), 1e-6, terms));
        EXPECT_TRUE(float_near(length(a), glm::length(to_glm(a)), 1e-6));
    }
    // Hand-derived: a 3-4-5 triangle, and the all-ones vector of length sqrt(n).
    V v{};
    v.x = 3;
    v.y = 4;
    EXPECT_FLOAT_EQ(length(v), 5.0f);
    EXPECT_FLOAT_EQ(length(splat<V>(1.0f)), std::sqrt(float(VecTraits<V>::n)));
    EXPECT_FLOAT_EQ(length(-v), 5.0f);
}

TYPED_TEST(VecTest, NormalizeMatchesGlmAndHasUnitLength) {
    using V = TypeParam;
    Rng rng(103);
    for (int it = 0; it < 500; ++it) {
        // Magnitudes spread over six orders of magnitude.
        float magnitude = std::pow(10.0f, rng.uniform(-3, 3));
        V a = VecTraits<V>::random(rng, -1, 1) * magnitude;
        if (length(a) == 0) continue;
        V n = normalize(a);
        EXPECT_TRUE(vec_near(n, glm::normalize(to_glm(a)), 1e-6f));
        EXPECT_TRUE(float_near(length(n), 1.0, 1e-6));
        // Same direction: n is a positive multiple of a.
        EXPECT_GT(dot(n, a), 0.0f);
    }
}

TYPED_TEST(VecTest, NormalizeOfZeroOrNonFiniteIsTheZeroVectorNeverNaN) {
    using V = TypeParam;
    EXPECT_EQ(normalize(V{}), V{});
    EXPECT_EQ(normalize(-V{}), V{});  // negative zero
    for (int i = 0; i < VecTraits<V>::n; ++i) {
        for (float bad : {k_nan, k_inf, -k_inf}) {
            V v = splat<V>(1.0f);
            v[static_cast<std::size_t>(i)] = bad;
            V n = normalize(v);
            EXPECT_TRUE(is_finite(n)) << "component " << i << " = " << bad;
            EXPECT_EQ(n, V{}) << "component " << i << " = " << bad;
        }
    }
    EXPECT_EQ(normalize(splat<V>(k_nan)), V{});
    // Vectors whose squared length underflows (1e-30) or overflows (1e30) still have a direction:
    // they are rescaled first and come out unit length, pointing the same way.
    for (float scale : {1e-30f, 1e30f, -3e37f}) {
        V v = splat<V>(scale);
        v[0] = 2 * scale;
        const V n = normalize(v);
        EXPECT_TRUE(is_finite(n)) << scale;
        EXPECT_NEAR(length(n), 1.0f, 1e-6f) << scale;
        EXPECT_GT(dot(n, v / std::fabs(scale)), 0.0f) << scale;  // same direction as v
        EXPECT_NEAR(n[0], 2 * n[1], 1e-6f) << scale;
    }
    // The smallest denormal still has a direction; only exact zero has none.
    V denormal{};
    denormal[0] = std::numeric_limits<float>::denorm_min();
    EXPECT_EQ(normalize(denormal)[0], 1.0f);
}

TYPED_TEST(VecTest, IsFiniteDetectsNaNAndInfinity) {
    using V = TypeParam;
    EXPECT_TRUE(is_finite(splat<V>(3.0f)));
    for (int i = 0; i < VecTraits<V>::n; ++i)
        for (float bad : {k_nan, k_inf, -k_inf}) {
            V v = splat<V>(3.0f);
            v[static_cast<std::size_t>(i)] = bad;
            EXPECT_FALSE(is_finite(v));
        }
}

TYPED_TEST(VecTest, MixAndClampMatchGlm) {
    using V = TypeParam;
    Rng rng(104);
    for (int it = 0; it < 500; ++it) {
        V a = VecTraits<V>::random(rng, -10, 10);
        V b = VecTraits<V>::random(rng, -10, 10);
        float t = rng.uniform(-0.5f, 1.5f);
        // GLM evaluates a*(1-t) + b*t, facet a + (b-a)*t: equal up to rounding of terms of size ~|a|+|b|.
        EXPECT_TRUE(vec_near(mix(a, b, t), glm::mix(to_glm(a), to_glm(b), t), 1e-5f));
        float lo = rng.uniform(-5, 0), hi = rng.uniform(0, 5);
        EXPECT_EQ(clamp(a, lo, hi), from_glm(glm::clamp(to_glm(a), lo, hi)));
    }
    // Hand-derived end points and midpoint.
    V a = splat<V>(2.0f), b = splat<V>(6.0f);
    EXPECT_EQ(mix(a, b, 0.0f), a);
    EXPECT_EQ(mix(a, b, 1.0f), b);
    EXPECT_EQ(mix(a, b, 0.5f), splat<V>(4.0f));
    EXPECT_EQ(mix(a, b, 0.25f), splat<V>(3.0f));
    EXPECT_EQ(clamp(splat<V>(7.0f), 0.0f, 1.0f), splat<V>(1.0f));
    EXPECT_EQ(clamp(splat<V>(-7.0f), 0.0f, 1.0f), splat<V>(0.0f));
    EXPECT_EQ(clamp(splat<V>(0.25f), 0.0f, 1.0f), splat<V>(0.25f));
}

TYPED_TEST(VecTest, MinMaxPickPerComponent) {
    using V = TypeParam;
    V a, b;
    for (int i = 0; i < VecTraits<V>::n; ++i) {
        // Alternate which argument holds the smaller value.
        a[static_cast<std::size_t>(i)] = i % 2 ? 1.0f : -1.0f;
        b[static_cast<std::size_t>(i)] = i % 2 ? -2.0f : 2.0f;
    }
    V lo = min(a, b), hi = max(a, b);
    for (int i = 0; i < VecTraits<V>::n; ++i) {
        EXPECT_EQ(lo[static_cast<std::size_t>(i)], i % 2 ? -2.0f : -1.0f);
        EXPECT_EQ(hi[static_cast<std::size_t>(i)], i % 2 ? 1.0f : 2.0f);
    }
}

// ---- Vec3 only: cross product ---------------------------------------------------------------------

TEST(Vec3Cross, FollowsTheRightHandRule) {
    const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    EXPECT_EQ(cross(x, y), z);
    EXPECT_EQ(cross(y, z), x);
    EXPECT_EQ(cross(z, x), y);
    EXPECT_EQ(cross(y, x), -z);
    EXPECT_EQ(cross(z, y), -x);
    EXPECT_EQ(cross(x, z), -y);
    EXPECT_EQ(cross(x, x), Vec3{});
    // Hand-derived: (1,2,3) x (4,5,6) = (2*6-3*5, 3*4-1*6, 1*5-2*4) = (-3, 6, -3).
    EXPECT_EQ(cross(Vec3{1, 2, 3}, Vec3{4, 5, 6}), (Vec3{-3, 6, -3}));
}

TEST(Vec3Cross, MatchesGlmAndIsPerpendicularAndAntiCommutative) {
    Rng rng(105);
    for (int it = 0; it < 1000; ++it) {
        Vec3 a = rng.vec3(-10, 10), b = rng.vec3(-10, 10);
        Vec3 c = cross(a, b);
        EXPECT_TRUE(vec_near(c, glm::cross(to_glm(a), to_glm(b)), 1e-6f));
        EXPECT_EQ(cross(b, a), -c);
        float scale = length(a) * length(b);
        EXPECT_TRUE(float_near(dot(c, a), 0.0, 1e-5, scale * length(a)));
        EXPECT_TRUE(float_near(dot(c, b), 0.0, 1e-5, scale * length(b)));
        // Lagrange's identity: |a x b|^2 = |a|^2 |b|^2 - (a.b)^2.
        double lagrange = double(dot(a, a)) * dot(b, b) - double(dot(a, b)) * dot(a, b);
        EXPECT_TRUE(float_near(dot(c, c), lagrange, 1e-5, double(scale) * scale));
    }
}

// ---- Vec4 helpers and scalar helpers ---------------------------------------------------------------

TEST(Vec4, ConstructsFromVec3AndReturnsXyz) {
    Vec4 v(Vec3{1, 2, 3}, 4);
    EXPECT_EQ(v, (Vec4{1, 2, 3, 4}));
    EXPECT_EQ(v.xyz(), (Vec3{1, 2, 3}));
    EXPECT_EQ(v[3], 4.0f);
}

TEST(ScalarHelpers, ClampMixRadiansDegrees) {
    EXPECT_EQ(facet::clamp(5.0f, 0.0f, 1.0f), 1.0f);
    EXPECT_EQ(facet::clamp(-5.0f, 0.0f, 1.0f), 0.0f);
    EXPECT_EQ(facet::clamp(0.5f, 0.0f, 1.0f), 0.5f);
    EXPECT_EQ(facet::mix(2.0f, 6.0f, 0.25f), 3.0f);
    EXPECT_TRUE(float_near(facet::radians(180.0f), 3.14159265358979, 1e-7));
    EXPECT_TRUE(float_near(facet::radians(90.0f), glm::radians(90.0f), 1e-7));
    EXPECT_TRUE(float_near(facet::degrees(facet::k_pi / 3), 60.0, 1e-6));
    EXPECT_TRUE(float_near(facet::degrees(1.0f), glm::degrees(1.0f), 1e-7));
    Rng rng(106);
    for (int it = 0; it < 100; ++it) {
        float d = rng.uniform(-720, 720);
        EXPECT_TRUE(float_near(facet::degrees(facet::radians(d)), d, 1e-6, 1.0));
    }
}

}  // namespace
