// facet simd: Highway's run-time part (which targets the CPU runs, the chosen one, where assertions
// end), compiled in. In: CPUID and the registers the OS saves; out: Highway target bits. Not the
// kernels, nor facet's ISA selection (isa.cpp). Why not libhwy.so: it is a C++ library, so loading it
// loads libstdc++.so, whose ~1,700 symbol bindings cost every facet process 0.7 ms before `main`
// (docs/BENCHMARKS.md); without it the `facet` executable links libstdc++ statically.
#include <hwy/base.h>
#include <hwy/targets.h>

#include <atomic>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#if HWY_ARCH_X86
#include <cpuid.h>
#endif

namespace hwy {
namespace {

std::atomic<std::int64_t> g_for_test{0};  // SetSupportedTargetsForTest's mask (0: none)
std::atomic<std::int64_t> g_disabled{0};  // DisableTargets'

#if defined(HWY_COMPILE_ONLY_SCALAR) || HWY_BROKEN_EMU128
constexpr std::int64_t k_portable = HWY_SCALAR;
#else
constexpr std::int64_t k_portable = HWY_EMU128;
#endif

#if HWY_ARCH_X86
bool bit(std::uint32_t reg, int i) { return (reg >> i & 1) != 0; }

// Highway's requirements: each x86 target needs its own features and those of the targets below it.
std::int64_t detect() {
    std::int64_t targets = k_portable;
    std::uint32_t a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(0, &a, &b, &c, &d)) return targets;
    const std::uint32_t max_level = a;
    __cpuid(1, a, b, c, d);
    const bool ssse3 = bit(d, 25) && bit(d, 26) && bit(c, 0) && bit(c, 9);    // SSE, SSE2, SSE3, SSSE3
    const bool sse4 = ssse3 && bit(c, 19) && bit(c, 20) && bit(c, 1) && bit(c, 25);  // 4.1, 4.2, CLMUL, AES
    const bool avx_fma_f16c = bit(c, 28) && bit(c, 12) && bit(c, 29);
    const bool osxsave = bit(c, 27);
    std::uint32_t extended = 0;
    if (__get_cpuid(0x80000001u, &a, &b, &c, &d)) extended = c;
    std::uint32_t b7 = 0, c7 = 0;
    if (max_level >= 7) __cpuid_count(7, 0, a, b7, c7, d);
    const bool avx2 = sse4 && avx_fma_f16c && bit(extended, 5) && bit(b7, 3) && bit(b7, 5) && bit(b7, 8);  // LZCNT, BMI, AVX2, BMI2
    const bool avx3 = avx2 && bit(b7, 16) && bit(b7, 17) && bit(b7, 30) && bit(b7, 31);  // AVX-512 F, DQ, BW, VL
    // VBMI, VBMI2, VAES, VPCLMULQDQ, VNNI, BITALG, VPOPCNTDQ
    const bool avx3_dl = avx3 && bit(c7, 1) && bit(c7, 6) && bit(c7, 9) && bit(c7, 10) && bit(c7, 11) && bit(c7, 12) && bit(c7, 14);
    // The registers the OS saves on a context switch (XCR0): XMM, YMM, the AVX-512 masks and ZMM.
    std::uint32_t xcr0 = 0;
    if (osxsave) {
        std::uint32_t high = 0;
        asm volatile("xgetbv" : "=a"(xcr0), "=d"(high) : "c"(0));
    }
    const bool xmm = !osxsave || bit(xcr0, 1);
    const bool ymm = osxsave && bit(xcr0, 1) && bit(xcr0, 2);
    const bool zmm = ymm && bit(xcr0, 5) && bit(xcr0, 6) && bit(xcr0, 7);
    if (ssse3 && xmm) targets |= HWY_SSSE3;
    if (sse4 && xmm) targets |= HWY_SSE4;
    if (avx2 && ymm) targets |= HWY_AVX2;
    if (avx3 && zmm) targets |= HWY_AVX3;
    if (avx3_dl && zmm) targets |= HWY_AVX3_DL;
    return targets;
}
#else
// Elsewhere the targets the compiler's flags guarantee (no dispatch above them).
std::int64_t detect() { return k_portable | HWY_ENABLED_BASELINE; }
#endif

}  // namespace

// What this CPU runs (detected once: it does not change under a process), or the test's mask, less
// the disabled targets; never 0.
std::int64_t SupportedTargets() {
    static const std::int64_t detected = detect();
    std::int64_t targets = g_for_test.load(std::memory_order_relaxed);
    if (targets == 0) targets = detected;
    targets &= ~g_disabled.load(std::memory_order_relaxed);
    return targets == 0 ? HWY_STATIC_TARGET : targets;
}

// Both take effect at the next dispatch: the chosen target is reset, and the next call through a
// dispatch table chooses again from SupportedTargets.
void DisableTargets(std::int64_t disabled_targets) {
    g_disabled.store(disabled_targets, std::memory_order_relaxed);
    GetChosenTarget().DeInit();
}

void SetSupportedTargetsForTest(std::int64_t targets) {
    g_for_test.store(targets, std::memory_order_relaxed);
    GetChosenTarget().DeInit();
}

// Where Highway's assertions end (HWY_ASSERT; HWY_DASSERT in debug builds).
void Abort(const char* file, int line, const char* format, ...) {
    std::fprintf(stderr, "Abort at %s:%d: ", file, line);
    std::va_list args;
    va_start(args, format);
    std::vfprintf(stderr, format, args);
    va_end(args);
    std::fputc('\n', stderr);
    std::abort();
}

ChosenTarget& GetChosenTarget() {
    static ChosenTarget chosen;  // constant-initialized: no guard
    return chosen;
}

}  // namespace hwy
