// facet simd: the ISA switch. Highway compiles each kernel once per target and dispatches to the best
// one the CPU supports among those allowed; selecting an ISA allows only the targets at or below it.
// "scalar" bypasses Highway and runs the reference kernels (simd/isa.hpp: use_scalar_kernels()).
#include "facet/isa.hpp"

#include <hwy/targets.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>

#include "simd/isa.hpp"

namespace facet {
namespace {

struct IsaName {
    const char* name;
    std::int64_t targets;  // Highway targets that count as this ISA
};

// Best first. avx512 is Highway's AVX3 family (Skylake-X and later, Zen 4).
constexpr std::array<IsaName, 3> k_isas{{{"avx512", HWY_AVX3 | HWY_AVX3_DL
#ifdef HWY_AVX3_ZEN4
                                                        | HWY_AVX3_ZEN4
#endif
                                          },
                                         {"avx2", HWY_AVX2},
                                         {"sse4", HWY_SSE4}}};
constexpr int k_best = -1;

std::atomic<bool> g_scalar{false};
std::atomic<int> g_selected{k_best};  // index into k_isas

bool cpu_has(const IsaName& isa) { return (detail::cpu_targets() & isa.targets & HWY_TARGETS) != 0; }

}  // namespace

namespace detail {

std::int64_t cpu_targets() {
    // What the CPU supports, read once before any selection narrows Highway's view.
    static const std::int64_t targets = [] {
        hwy::SetSupportedTargetsForTest(0);
        return hwy::SupportedTargets();
    }();
    return targets;
}

bool use_scalar_kernels() { return g_scalar.load(std::memory_order_relaxed); }

}  // namespace detail

std::vector<std::string> available_isas() {
    std::vector<std::string> out;
    for (const IsaName& isa : k_isas)
        if (cpu_has(isa)) out.emplace_back(isa.name);
    out.emplace_back("scalar");
    return out;
}

std::string active_isa() {
    if (g_scalar.load()) return "scalar";
    for (int i = std::max(g_selected.load(), 0); i < static_cast<int>(k_isas.size()); ++i)
        if (cpu_has(k_isas[static_cast<std::size_t>(i)])) return k_isas[static_cast<std::size_t>(i)].name;
    return "scalar";  // a CPU below SSE4: Highway's portable target, which computes the same bytes
}

bool select_isa(std::string_view name) {
    const std::int64_t cpu = detail::cpu_targets();
    int index = -2;
    if (name == "best" || name == "scalar") index = k_best;
    for (std::size_t i = 0; i < k_isas.size(); ++i)
        if (name == k_isas[i].name && cpu_has(k_isas[i])) index = static_cast<int>(i);
    if (index == -2) return false;

    std::int64_t allowed = 0;  // 0: no restriction
    if (index != k_best) {
        allowed = HWY_EMU128 | HWY_SCALAR;
        for (std::size_t j = static_cast<std::size_t>(index); j < k_isas.size(); ++j) allowed |= k_isas[j].targets;
        allowed &= cpu;
    }
    hwy::SetSupportedTargetsForTest(allowed);
    (void)hwy::SupportedTargets();  // makes Highway re-choose the dispatched targets now
    g_selected = index;
    g_scalar = name == "scalar";
    return true;
}

}  // namespace facet
