// facet math: the natural and decimal logarithms with the same bits on every machine, beside the
// trigonometric functions of math/portable_trig.hpp and for the same reason: glibc picks its log and
// log10 per CPU at run time (FMA or not), and they may differ in the last bit. These use double
// additions, subtractions, multiplications and divisions only, in a fixed order (the library builds
// with -ffp-contract=off). Used where a value is computed once and shown or compared: the PSNR of
// facet::compare_images. Accuracy (measured against long double over 2 million arguments across
// every binade, densely around 1 and over PSNR's range): log 0.81, log10 0.72 units in the last place
// of double; log 1 = 0 and log10 of 10^k = k exactly for k = 0..22 (the powers of ten a double holds).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace facet::portable {

namespace detail {
// ln 2 in two parts (fdlibm's): the high part has 32 trailing zero bits, so e * k_ln2_hi is exact for
// every exponent e of a double.
constexpr double k_ln2_hi = 6.93147180369123816490e-01;
constexpr double k_ln2_lo = 1.90821492927058770002e-10;
constexpr double k_sqrt_half = 0.70710678118654752440;

// x = 2^e (1 + f) with 1 + f in [sqrt(1/2), sqrt(2)) (frexp, then one fold; f exact), and
// log(1 + f) = f - f^2/2 + s (f^2/2 + R): s = f / (2 + f), |s| <= 0.172, and
// log(1 + f) = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...), whose series is taken to s^25 (the next term
// is below 2^-60 of the sum) with R = 2 (s^2/3 + ... + s^24/25). fdlibm's arrangement: the rounding
// of s only touches the small correction s (f^2/2 + R). For x > 0 finite.
inline void log_parts(double x, int& e, double& f, double& half_f2, double& correction) {
    double m = std::frexp(x, &e);  // m in [1/2, 1), subnormals included
    if (m < k_sqrt_half) {
        m = 2 * m;
        --e;
    }
    f = m - 1;  // exact: m and 1 are within a factor of 2
    const double s = f / (2 + f), z = s * s;
    double r = 0;  // R, Horner from the highest term
    for (int k = 12; k >= 1; --k) r = z * (2.0 / (2 * k + 1) + r);
    half_f2 = 0.5 * f * f;
    correction = s * (half_f2 + r);
}

// log 0 = -inf, negative = NaN, inf = inf, NaN = NaN; false when x is none of those.
inline bool log_special(double x, double& result) {
    if (x > 0 && x < std::numeric_limits<double>::infinity()) return false;
    result = x == 0 ? -std::numeric_limits<double>::infinity()
                    : x > 0 ? x : std::numeric_limits<double>::quiet_NaN();
    return true;
}
}  // namespace detail

// log x = e ln 2 + log(1 + f), ln 2 in two parts.
inline double log(double x) {
    double result;
    if (detail::log_special(x, result)) return result;
    int e;
    double f, half_f2, correction;
    detail::log_parts(x, e, f, half_f2, correction);
    const double de = e;
    return de * detail::k_ln2_hi - ((half_f2 - (correction + de * detail::k_ln2_lo)) - f);
}

// log10 x = e log10(2) + log(1 + f) / ln 10 (fdlibm's, FreeBSD's e_log10.c): f - f^2/2 is split
// into its high 21 bits and the rest, and 1 / ln 10 and log10(2) are in two parts, so the sum keeps
// the bits a single rounded product would lose (and 10^k gives k exactly).
inline double log10(double x) {
    constexpr double k_inv_ln10_hi = 4.34294481878168880939e-01;  // 32 significant bits
    constexpr double k_inv_ln10_lo = 2.50829467116452752298e-11;
    constexpr double k_log10_2_hi = 3.01029995663611771306e-01;  // 40 significant bits
    constexpr double k_log10_2_lo = 3.69423907715893078616e-13;
    double result;
    if (detail::log_special(x, result)) return result;
    int e;
    double f, half_f2, correction;
    detail::log_parts(x, e, f, half_f2, correction);
    const double hi = std::bit_cast<double>(std::bit_cast<std::uint64_t>(f - half_f2) & 0xffffffff00000000ull);
    const double lo = (f - hi) - half_f2 + correction;
    const double de = e;
    const double e_hi = de * k_log10_2_hi;
    const double f_hi = hi * k_inv_ln10_hi;
    double low = de * k_log10_2_lo + (lo + hi) * k_inv_ln10_lo + lo * k_inv_ln10_hi;
    const double sum = e_hi + f_hi;
    low += (e_hi - sum) + f_hi;  // what the sum rounded away
    return low + sum;
}

}  // namespace facet::portable
