// facet: which instruction set the SIMD kernels use. By default the best one the CPU supports,
// chosen at run time (Google Highway's dynamic dispatch); a lower one can be forced, e.g. to compare
// or to work around a machine. "scalar" runs the plain C++ kernels that serve as the specification.
// Every ISA produces the same image, byte for byte (tests/unit/isa_test.cpp checks it).
// Process-wide setting: change it between frames, not while a Renderer is drawing.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet {

// Names usable on this CPU, best first, "scalar" last: e.g. {"avx512", "avx2", "sse4", "scalar"}.
std::vector<std::string> available_isas();

// The ISA the kernels use now.
std::string active_isa();

// Uses `name` ("best" restores the default). Returns false, changing nothing, when the name is
// unknown or the CPU cannot run it.
bool select_isa(std::string_view name);

}  // namespace facet
FACET_API_END
