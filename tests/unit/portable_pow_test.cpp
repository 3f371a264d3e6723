// portable_pow: close to std::pow over the range shaders use, exact at the special values, and
// the same value wherever it is computed (the SIMD lanes are tested in CompiledVisiblePass.*).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "facet/math/portable_pow.hpp"

namespace {

using facet::portable_pow;

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

}  // namespace
