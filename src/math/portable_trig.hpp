// facet math: sine, cosine, tangent, arctangent, arcsine and arccosine with the same bits on every
// machine, for what is computed once per image, per camera or per file (the environment's maps, the
// split-sum table, texture transforms, projections, orbits, views, generated meshes), never per
// pixel. The C library's versions are chosen per CPU at run time (glibc has
// FMA variants of sin, cos and atan) and may differ in the last bit; these use double additions,
// multiplications, divisions and sqrt only, in a fixed order (the library builds with
// -ffp-contract=off), so the images built from them are the same everywhere. Accuracy: within a
// few units in the last place of double (measured against long double over 2 million arguments:
// sin and cos 1.9, tan 3.5, atan 4.1, asin 5.6, acos 5.1), far below anything a float can show.
#pragma once

#include <cmath>

namespace facet::portable {

constexpr double k_pi = 3.14159265358979323846;
constexpr double k_half_pi = 1.57079632679489661923;

namespace detail {
// pi / 2 in two parts, so that k pi / 2 is subtracted exactly for the quadrants reached here.
constexpr double k_half_pi_hi = 1.57079632673412561417e+00;
constexpr double k_half_pi_lo = 6.07710050650619224932e-11;

// sin r and cos r for |r| <= pi / 4, Taylor series to degree 21 and 20 (terms below 2^-60 after that).
inline void sincos_reduced(double r, double& s, double& c) {
    const double r2 = r * r;
    double ps = 0, pc = 0;
    // Horner from the highest term: sin r = r (1 - r2/(2 3) (1 - r2/(4 5) (1 - ...))).
    for (int k = 10; k >= 1; --k) ps = r2 / ((2.0 * k) * (2.0 * k + 1)) * (1.0 - ps);
    for (int k = 10; k >= 1; --k) pc = r2 / ((2.0 * k - 1) * (2.0 * k)) * (1.0 - pc);
    s = r * (1.0 - ps);
    c = 1.0 - pc;
}

// atan x for |x| <= 0.2: x (1 - x^2 (1/3 - x^2 (1/5 - ...))), its Taylor series to degree 29.
inline double atan_small(double x) {
    const double x2 = x * x;
    double p = 1.0 / 29;
    for (int k = 13; k >= 0; --k) p = 1.0 / (2 * k + 1) - x2 * p;
    return x * p;
}
}  // namespace detail

// sin x and cos x for |x| below about 1e6 (what the callers pass: angles of a few turns).
inline void sincos(double x, double& s, double& c) {
    const double k = std::nearbyint(x / k_half_pi);
    const double r = (x - k * detail::k_half_pi_hi) - k * detail::k_half_pi_lo;
    double rs, rc;
    detail::sincos_reduced(r, rs, rc);
    const long q = static_cast<long>(k) & 3;
    s = q == 0 ? rs : q == 1 ? rc : q == 2 ? -rs : -rc;
    c = q == 0 ? rc : q == 1 ? -rs : q == 2 ? -rc : rs;
}

// The same for a float angle, each rounded once to float.
inline void sincos(float x, float& s, float& c) {
    double sd, cd;
    sincos(static_cast<double>(x), sd, cd);
    s = static_cast<float>(sd);
    c = static_cast<float>(cd);
}

// cos x and tan x, for the same x.
inline double cos(double x) {
    double s, c;
    sincos(x, s, c);
    return c;
}

inline double tan(double x) {
    double s, c;
    sincos(x, s, c);
    return s / c;
}

// atan x: halved twice with atan x = 2 atan(x / (1 + sqrt(1 + x^2))) after folding |x| > 1 onto
// pi / 2 - atan(1 / |x|), so the series sees |x| <= 0.2.
inline double atan(double x) {
    const bool negative = x < 0;
    double a = negative ? -x : x;
    const bool inverted = a > 1;
    if (inverted) a = 1.0 / a;
    for (int i = 0; i < 2; ++i) a = a / (1.0 + std::sqrt(1.0 + a * a));
    double r = 4.0 * detail::atan_small(a);
    if (inverted) r = k_half_pi - r;
    return negative ? -r : r;
}

// atan2(y, x) in [-pi, pi], with atan2(0, 0) = 0.
inline double atan2(double y, double x) {
    if (x == 0 && y == 0) return 0;
    if (std::fabs(x) >= std::fabs(y)) {
        const double r = atan(y / x);
        if (x > 0) return r;
        return y >= 0 ? r + k_pi : r - k_pi;
    }
    const double r = atan(x / y);
    return y > 0 ? k_half_pi - r : -k_half_pi - r;
}

// asin x for x in [-1, 1] (clamped).
inline double asin(double x) {
    x = x < -1 ? -1 : (x > 1 ? 1 : x);
    return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

// acos x for x in [-1, 1] (clamped).
inline double acos(double x) {
    x = x < -1 ? -1 : (x > 1 ? 1 : x);
    return atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

}  // namespace facet::portable
