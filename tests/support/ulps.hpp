// Test support: the error of a double result in units of double's last place, against a long double
// reference (the C library's long double functions carry 11 bits beyond double's), for the tests of
// the portable math functions.
#pragma once

#include <cmath>
#include <limits>

namespace facet_test {

// Error in units of double's last place at the exact value.
inline double ulps(double r, long double exact) {
    const double e = static_cast<double>(exact);
    const double u = std::nextafter(std::fabs(e), std::numeric_limits<double>::infinity()) - std::fabs(e);
    return static_cast<double>(std::fabs(static_cast<long double>(r) - exact)) / u;
}

}  // namespace facet_test
