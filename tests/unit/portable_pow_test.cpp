// portable_pow and portable_log2: close to std::pow and log2 in double over the range shaders use,
// exact at the special values and powers of two, and the same value wherever it is computed (the SIMD
// lanes are tested in CompiledVisiblePass.*). portable:: sine, cosine, tangent and the inverses
// (math/portable_trig.hpp): within a few units of double of long double's.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "facet/math/portable_pow.hpp"
#include "math/portable_trig.hpp"
#include "support/ulps.hpp"

namespace {

using facet_test::ulps;

using facet::portable_log2;
using facet::portable_pow;

// Units in the last place of float at r (the spacing of floats around it).
double ulp(float r) { return std::nextafter(std::fabs(r), std::numeric_limits<float>::infinity()) - std::fabs(r); }

// The documented accuracy: relative error below 2e-6 for |y log2 x| < 16, below 1e-5 up to 128.
TEST(PortablePow, IsAsCloseToStdPowAsDocumented) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> log_x(-40.0f, 40.0f);
    double worst_small = 0, worst_large = 0;
    int small = 0, large = 0;
    for (float y : {0.5f, 1.0f, 2.0f, 3.7f, 8.0f, 40.0f, 127.0f, -1.0f, -2.5f}) {
        for (int i = 0; i < 20000; ++i) {
            const float x = std::exp2(log_x(rng));
            const double exact = std::pow(static_cast<double>(x), static_cast<double>(y));
            if (exact < 0x1p-125 || exact > 0x1p127) continue;  // outside the documented range
            const double rel = std::fabs(portable_pow(x, y) - exact) / exact;
            if (std::fabs(std::log2(exact)) < 16) {
                worst_small = std::max(worst_small, rel);
                ++small;
            } else {
                worst_large = std::max(worst_large, rel);
                ++large;
            }
        }
    }
    EXPECT_GT(small, 10000);
    EXPECT_GT(large, 10000);
    EXPECT_LT(worst_small, 2e-6);
    EXPECT_LT(worst_large, 1e-5);
}

TEST(PortablePow, CoversSubnormalBases) {
    const float x = 0x1p-140f;  // subnormal
    EXPECT_NEAR(portable_pow(x, 0.5f) / 0x1p-70f, 1.0f, 3e-6f);
    EXPECT_NEAR(portable_pow(x, -0.5f) / 0x1p70f, 1.0f, 3e-6f);
}

TEST(PortablePow, SpecialValues) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(portable_pow(1.0f, 40.0f), 1.0f);
    EXPECT_EQ(portable_pow(2.0f, 10.0f), 1024.0f);
    EXPECT_EQ(portable_pow(0.25f, 0.5f), 0.5f);
    EXPECT_EQ(portable_pow(0.0f, 40.0f), 0.0f);
    EXPECT_EQ(portable_pow(0.0f, -1.0f), inf);
    EXPECT_EQ(portable_pow(nan, 0.0f), 1.0f);
    EXPECT_EQ(portable_pow(0.3f, 0.0f), 1.0f);
    EXPECT_TRUE(std::isnan(portable_pow(-0.5f, 2.0f)));
    EXPECT_TRUE(std::isnan(portable_pow(nan, 2.0f)));
    EXPECT_TRUE(std::isnan(portable_pow(0.5f, nan)));
    EXPECT_EQ(portable_pow(inf, 2.0f), inf);
    EXPECT_EQ(portable_pow(inf, -2.0f), 0.0f);
    EXPECT_EQ(portable_pow(1e-30f, 10.0f), 0.0f);  // below 2^-126
    EXPECT_EQ(portable_pow(1e30f, 10.0f), inf);    // above 2^128
    EXPECT_EQ(portable_pow(0.5f, 126.5f), 0.0f);  // 2^-126.5: below 2^-126
    EXPECT_GT(portable_pow(0.5f, 125.5f), 0.0f);
    EXPECT_LT(portable_pow(2.0f, 127.9f), std::numeric_limits<float>::max());  // 2^i built in two halves
}

TEST(PortableLog2, ExactAtEveryPowerOfTwoAndTheSpecialValues) {
    for (int k = -149; k <= 127; ++k) EXPECT_EQ(portable_log2(std::ldexp(1.0f, k)), static_cast<float>(k)) << k;
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(portable_log2(0.0f), -inf);
    EXPECT_EQ(portable_log2(-0.0f), -inf);
    EXPECT_EQ(portable_log2(inf), inf);
    EXPECT_TRUE(std::isnan(portable_log2(-1.0f)));
    EXPECT_TRUE(std::isnan(portable_log2(-inf)));
    EXPECT_TRUE(std::isnan(portable_log2(nan)));
}

// The documented accuracy (3.004 units at worst over every float), against log2 in double, over
// floats spread across every binade (subnormals included) and densely around 1.
TEST(PortableLog2, IsWithinThreeUnitsInTheLastPlace) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> bits(1, 0x7f7fffffu);  // every positive finite float
    std::uniform_real_distribution<float> near_one(0.5f, 2.0f);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const float x = i % 2 ? std::bit_cast<float>(bits(rng)) : near_one(rng);
        const float r = portable_log2(x);
        const double exact = std::log2(static_cast<double>(x));
        if (exact == 0) {
            EXPECT_EQ(r, 0.0f);
            continue;
        }
        worst = std::max(worst, std::fabs(r - exact) / ulp(static_cast<float>(exact)));
    }
    EXPECT_LE(worst, 3.01);
}

// Against the C library's long double functions (64-bit significands: 11 bits beyond double's),
// over angles of a few turns and the whole domain of the inverses.
TEST(PortableTrig, WithinAFewUnitsOfDoubleOfLongDouble) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(-20.0, 20.0), unit(-1.0, 1.0), any(-50.0, 50.0);
    double worst_sin = 0, worst_cos = 0, worst_tan = 0, worst_atan = 0, worst_asin = 0, worst_acos = 0;
    for (int i = 0; i < 20000; ++i) {
        const double x = angle(rng), u = unit(rng), a = any(rng);
        double s, c;
        facet::portable::sincos(x, s, c);
        const long double lx = x;
        worst_sin = std::max(worst_sin, ulps(s, std::sin(lx)));
        worst_cos = std::max(worst_cos, ulps(c, std::cos(lx)));
        worst_tan = std::max(worst_tan, ulps(facet::portable::tan(x), std::tan(lx)));
        worst_atan = std::max(worst_atan, ulps(facet::portable::atan(a), std::atan(static_cast<long double>(a))));
        worst_asin = std::max(worst_asin, ulps(facet::portable::asin(u), std::asin(static_cast<long double>(u))));
        worst_acos = std::max(worst_acos, ulps(facet::portable::acos(u), std::acos(static_cast<long double>(u))));
    }
    // The header's measured worst cases (over 2 million arguments), with a little room.
    EXPECT_LE(worst_sin, 2.5);
    EXPECT_LE(worst_cos, 2.5);
    EXPECT_LE(worst_tan, 4.5);
    EXPECT_LE(worst_atan, 5.0);
    EXPECT_LE(worst_asin, 6.5);
    EXPECT_LE(worst_acos, 6.0);
}

TEST(PortableTrig, ExactValues) {
    double s, c;
    facet::portable::sincos(0.0, s, c);
    EXPECT_EQ(s, 0.0);
    EXPECT_EQ(c, 1.0);
    float sf, cf;
    facet::portable::sincos(0.0f, sf, cf);
    EXPECT_EQ(sf, 0.0f);
    EXPECT_EQ(cf, 1.0f);
    EXPECT_EQ(facet::portable::tan(0.0), 0.0);
    EXPECT_EQ(facet::portable::cos(0.0), 1.0);
    EXPECT_EQ(facet::portable::asin(0.0), 0.0);
    EXPECT_EQ(facet::portable::asin(1.0), facet::portable::k_half_pi);
    EXPECT_EQ(facet::portable::asin(-1.0), -facet::portable::k_half_pi);
    EXPECT_EQ(facet::portable::asin(2.0), facet::portable::k_half_pi);  // clamped
    EXPECT_EQ(facet::portable::acos(1.0), 0.0);
    EXPECT_EQ(facet::portable::acos(-1.0), facet::portable::k_pi);
    EXPECT_EQ(facet::portable::atan(0.0), 0.0);
    // The float forms are the double ones rounded once.
    for (float x : {0.1f, 0.5f, 1.0f, 2.5f, -3.0f, 10.0f}) {
        facet::portable::sincos(x, sf, cf);
        facet::portable::sincos(static_cast<double>(x), s, c);
        EXPECT_EQ(sf, static_cast<float>(s)) << x;
        EXPECT_EQ(cf, static_cast<float>(c)) << x;
    }
}

}  // namespace
