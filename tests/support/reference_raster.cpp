// Test support: the reference rasterizer (see reference_raster.hpp for the rule it implements).
#include "support/reference_raster.hpp"

#include <algorithm>
#include <cmath>

namespace facet_test::raster {
namespace {

// Cross product (b - a) x (p - a): positive, zero or negative as p is on one side of the line ab,
// on it, or on the other side.
std::int64_t side(Fixed a, Fixed b, Fixed p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

// Top edge: horizontal, and the triangle (where the third vertex c is) lies below it (larger y).
bool is_top_edge(Fixed a, Fixed b, Fixed c) { return a.y == b.y && c.y > a.y; }

// Left edge: not horizontal, and the triangle lies to its right: at the height of c, c is to the right
// of the line through a and b, i.e. c.x > a.x + (b.x - a.x) * (c.y - a.y) / (b.y - a.y), multiplied
// out by (b.y - a.y) (which flips the inequality when it is negative).
bool is_left_edge(Fixed a, Fixed b, Fixed c) {
    const std::int64_t dy = b.y - a.y;
    if (dy == 0) return false;
    const std::int64_t lhs = (c.x - a.x) * dy, rhs = (b.x - a.x) * (c.y - a.y);
    return dy > 0 ? lhs > rhs : lhs < rhs;
}

std::int64_t floor_div(std::int64_t n, std::int64_t d) {  // d > 0
    return n >= 0 ? n / d : -((-n + d - 1) / d);
}
std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }  // d > 0

// Pixel index range [lo, hi] that can contain covered centres, given fixed-point bounds: a superset
// (one pixel wider on each side); covers() decides exactly.
void candidate_range(std::int64_t lo, std::int64_t hi, int box_lo, int box_hi, std::int64_t& first,
                     std::int64_t& last) {
    first = std::max<std::int64_t>(box_lo, floor_div(lo, k_sub) - 1);
    last = std::min<std::int64_t>(box_hi - 1, floor_div(hi, k_sub) + 1);
}

}  // namespace

std::int64_t signed_area2(Fixed a, Fixed b, Fixed c) { return side(a, b, c); }

bool covers(const Fixed (&v)[3], Fixed p) {
    const std::int64_t area = side(v[0], v[1], v[2]);
    if (area == 0) return false;
    // The interior lies on the side of each edge where the opposite vertex is: the sign of `area`.
    const std::int64_t orientation = area > 0 ? 1 : -1;
    for (int e = 0; e < 3; ++e) {
        const Fixed a = v[e], b = v[(e + 1) % 3], c = v[(e + 2) % 3];
        const std::int64_t d = orientation * side(a, b, p);
        if (d > 0) continue;   // strictly on the inner side of this edge
        if (d < 0) return false;
        // Exactly on the line through this edge (and, since the other edges are checked too, on the
        // edge itself): covered only by a top or a left edge.
        if (!is_top_edge(a, b, c) && !is_left_edge(a, b, c)) return false;
    }
    return true;
}

Mask rasterize(const Fixed (&v)[3], int width, int height, Box box) {
    Mask mask(static_cast<std::size_t>(width) * height, 0);
    box = {std::max(box.x0, 0), std::max(box.y0, 0), std::min(box.x1, width), std::min(box.y1, height)};
    std::vector<int> counts;  // reuse the accumulation path
    counts.assign(mask.size(), 0);
    rasterize_add(v, width, box, counts);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = counts[i] != 0;
    return mask;
}

void rasterize_add(const Fixed (&v)[3], int width, Box box, std::vector<int>& counts) {
    const std::int64_t min_x = std::min({v[0].x, v[1].x, v[2].x}), max_x = std::max({v[0].x, v[1].x, v[2].x});
    const std::int64_t min_y = std::min({v[0].y, v[1].y, v[2].y}), max_y = std::max({v[0].y, v[1].y, v[2].y});
    std::int64_t x0, x1, y0, y1;
    candidate_range(min_x, max_x, box.x0, box.x1, x0, x1);
    candidate_range(min_y, max_y, box.y0, box.y1, y0, y1);
    for (std::int64_t iy = y0; iy <= y1; ++iy)
        for (std::int64_t ix = x0; ix <= x1; ++ix)
            if (covers(v, pixel_centre(ix, iy))) ++counts[static_cast<std::size_t>(iy) * width + ix];
}

Mask polygon_coverage(const std::vector<Fixed>& poly, int width, int height) {
    Mask mask(static_cast<std::size_t>(width) * height, 0);
    std::vector<std::uint8_t> toggle(static_cast<std::size_t>(width) + 1);
    const std::size_t n = poly.size();
    for (int iy = 0; iy < height; ++iy) {
        const std::int64_t py = pixel_centre(0, iy).y;
        std::fill(toggle.begin(), toggle.end(), 0);
        for (std::size_t k = 0; k < n; ++k) {
            const Fixed a = poly[k], b = poly[(k + 1) % n];
            // The line y = py + e^2 crosses the edge iff py is in [min y, max y): no vertex is ever
            // exactly on it, and horizontal edges never cross it.
            if ((a.y > py) == (b.y > py)) continue;
            // Crossing at x = N / D (exact rational), D > 0.
            std::int64_t D = b.y - a.y, N = a.x * D + (b.x - a.x) * (py - a.y);
            if (D < 0) D = -D, N = -N;
            // The crossing is left of p + (e, e^2) iff N / D <= px = 256 i + 128, i.e. for all pixels
            // i >= ceil((N - 128 D) / (256 D)).
            const std::int64_t first = ceil_div(N - (k_sub / 2) * D, k_sub * D);
            toggle[static_cast<std::size_t>(std::clamp<std::int64_t>(first, 0, width))] ^= 1;
        }
        std::uint8_t parity = 0;
        for (int ix = 0; ix < width; ++ix) {
            parity ^= toggle[static_cast<std::size_t>(ix)];
            mask[static_cast<std::size_t>(iy) * width + ix] = parity;
        }
    }
    return mask;
}

facet::Vec4 clip_from_fixed(Fixed p, const facet::Rect& vp, float z, float w) {
    const double sx = static_cast<double>(p.x) / k_sub, sy = static_cast<double>(p.y) / k_sub;
    const double ndc_x = (sx - vp.x) * 2.0 / vp.width - 1.0;
    const double ndc_y = 1.0 - (sy - vp.y) * 2.0 / vp.height;
    return {static_cast<float>(ndc_x * w), static_cast<float>(ndc_y * w), z * w, w};
}

bool snaps_exactly(Fixed p, const facet::Rect& vp, float z, float w) {
    const facet::Vec4 c = clip_from_fixed(p, vp, z, w);
    const double exact_ndc_x = (static_cast<double>(p.x) / k_sub - vp.x) * 2.0 / vp.width - 1.0;
    const double exact_ndc_y = 1.0 - (static_cast<double>(p.y) / k_sub - vp.y) * 2.0 / vp.height;
    // The stored clip coordinates are the exact products.
    if (static_cast<double>(c.x) != exact_ndc_x * w || static_cast<double>(c.y) != exact_ndc_y * w) return false;
    // Division by w (either as x / w or as x * (1 / w)) is exact.
    const float q = 1.0f / c.w;
    const float nx = c.x * q, ny = c.y * q;
    if (nx != c.x / c.w || ny != c.y / c.w) return false;
    if (static_cast<double>(nx) != exact_ndc_x || static_cast<double>(ny) != exact_ndc_y) return false;
    // Every step of the viewport transform is exact in float.
    const float half_w = static_cast<float>(vp.width) * 0.5f, half_h = static_cast<float>(vp.height) * 0.5f;
    const float tx = nx + 1.0f, ty = 1.0f - ny;
    if (static_cast<double>(tx) != exact_ndc_x + 1.0 || static_cast<double>(ty) != 1.0 - exact_ndc_y) return false;
    const float sx = static_cast<float>(vp.x) + tx * half_w, sy = static_cast<float>(vp.y) + ty * half_h;
    if (static_cast<double>(sx) * k_sub != static_cast<double>(p.x)) return false;
    if (static_cast<double>(sy) * k_sub != static_cast<double>(p.y)) return false;
    return sx * static_cast<float>(k_sub) == static_cast<float>(p.x) &&
           sy * static_cast<float>(k_sub) == static_cast<float>(p.y) && std::isfinite(c.z);
}

}  // namespace facet_test::raster
