// What `facet` does before it starts working: the libraries the dynamic linker loads and initializes
// (no C++ library: Highway's run-time part is compiled in, libstdc++ linked in; apps/cli), and that
// compiled-in part: its choice of SIMD targets against the compiler's own reading of the CPU, its Abort.
#include <gtest/gtest.h>

#include <hwy/base.h>
#include <hwy/targets.h>

#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "simd/isa.hpp"
#include "support/cli.hpp"

namespace {

// The shared objects whose initializers ran in `facet --help`, as the dynamic linker reports them.
std::vector<std::string> initialized_libraries() {
    ::setenv("LD_DEBUG", "libs", 1);
    const facet_test::CliRun run = facet_test::run_facet({"--help"});
    ::unsetenv("LD_DEBUG");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    std::vector<std::string> out;
    std::istringstream lines(run.err);
    for (std::string line; std::getline(lines, line);)
        if (const std::size_t at = line.find("calling init: "); at != std::string::npos) out.push_back(line.substr(at + 14));
    return out;
}

TEST(Startup, FacetLoadsNoCxxLibrary) {
    const std::vector<std::string> libraries = initialized_libraries();
    ASSERT_FALSE(libraries.empty()) << "the dynamic linker reported no initializers (LD_DEBUG=libs)";
    bool libc = false;
    for (const std::string& library : libraries) {
        libc = libc || library.find("libc.so") != std::string::npos;
        EXPECT_EQ(library.find("libhwy"), std::string::npos) << library;
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)  // sanitizer builds link the shared ones
        EXPECT_EQ(library.find("libstdc++"), std::string::npos) << library;
        EXPECT_EQ(library.find("libgcc_s"), std::string::npos) << library;
#endif
    }
    EXPECT_TRUE(libc) << "libc.so's initializer not among those reported";
}

TEST(Startup, SimdTargetsAreTheOnesTheCompilerFindsOnThisCpu) {
    __builtin_cpu_init();
    const bool ssse3 = __builtin_cpu_supports("sse") && __builtin_cpu_supports("sse2") && __builtin_cpu_supports("sse3") &&
                       __builtin_cpu_supports("ssse3");
    const bool sse4 = ssse3 && __builtin_cpu_supports("sse4.1") && __builtin_cpu_supports("sse4.2") &&
                      __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("aes");
    const bool avx2 = sse4 && __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") &&
                      __builtin_cpu_supports("fma") && __builtin_cpu_supports("f16c") && __builtin_cpu_supports("lzcnt") &&
                      __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
    const bool avx3 = avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
    const bool avx3_dl = avx3 && __builtin_cpu_supports("avx512vnni") && __builtin_cpu_supports("vpclmulqdq") &&
                         __builtin_cpu_supports("avx512vbmi") && __builtin_cpu_supports("avx512vbmi2") &&
                         __builtin_cpu_supports("vaes") && __builtin_cpu_supports("avx512vpopcntdq") &&
                         __builtin_cpu_supports("avx512bitalg");
    const std::int64_t targets = facet::detail::cpu_targets();
    EXPECT_EQ((targets & HWY_SSSE3) != 0, ssse3);
    EXPECT_EQ((targets & HWY_SSE4) != 0, sse4);
    EXPECT_EQ((targets & HWY_AVX2) != 0, avx2);
    EXPECT_EQ((targets & HWY_AVX3) != 0, avx3);
    EXPECT_EQ((targets & HWY_AVX3_DL) != 0, avx3_dl);
    EXPECT_NE(targets & (HWY_EMU128 | HWY_SCALAR), 0) << "the portable target is always there";
}

// Highway's assertions (HWY_ASSERT; HWY_DASSERT in debug builds) end in the compiled-in Abort, which
// names the place and the condition.
TEST(StartupDeathTest, HighwaysAssertionsAbortNamingTheCondition) {
    const int two = 2;
    EXPECT_DEATH(HWY_ASSERT(two == 3), "Abort at .*startup_test.cpp:[0-9]+: Assert two == 3");
}

}  // namespace
