// Test support: comparing rendered pixels (where two images first differ, for a failure message) and
// putting the ISA selection back after a test that walks through the ISAs.
#pragma once

#include <string>
#include <vector>

#include "facet/image.hpp"
#include "facet/isa.hpp"

namespace facet_test {

// "pixel (x, y): r,g,b,a vs r,g,b,a" at the first difference of two images `width` pixels wide, or
// "identical".
inline std::string first_difference(const std::vector<facet::Rgba8>& a, const std::vector<facet::Rgba8>& b, int width) {
    auto text = [](facet::Rgba8 c) {
        return std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + "," + std::to_string(c.a);
    };
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
        if (a[i] != b[i])
            return "pixel (" + std::to_string(i % static_cast<std::size_t>(width)) + ", " +
                   std::to_string(i / static_cast<std::size_t>(width)) + "): " + text(a[i]) + " vs " + text(b[i]);
    return a.size() == b.size() ? "identical" : "different sizes";
}

// Selects the best ISA again when the test ends, however it ends.
struct IsaGuard {
    ~IsaGuard() { facet::select_isa("best"); }
};

}  // namespace facet_test
