// facet simd internals: what the dispatching kernels ask of the ISA switch (facet/isa.hpp).
#pragma once

#include <cstdint>

namespace facet::detail {

// Highway targets the CPU supports (independent of the current selection).
std::int64_t cpu_targets();

// True when "scalar" is selected: kernels run their plain C++ reference version.
bool use_scalar_kernels();

}  // namespace facet::detail
