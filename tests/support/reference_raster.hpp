// Test support: a tiny reference rasterizer written from the definition of facet's coverage rule,
// independent of the library's code, plus helpers that place clip-space vertices so that they snap
// exactly to chosen fixed-point screen positions.
//
// The rule (facet's documented convention, the D3D/GL top-left rule):
//   * screen origin top-left, y down; pixel (ix, iy) has its centre at (ix + 1/2, iy + 1/2);
//   * vertices are snapped to 1/256 pixel, so every coordinate here is an integer in 1/256 px;
//   * a pixel is covered iff its centre is strictly inside the triangle, or exactly on an edge that is
//     a top edge (horizontal, interior below it) or a left edge (not horizontal, interior to its right);
//   * zero-area triangles cover nothing; the winding does not matter.
// Everything is evaluated directly, pixel by pixel, with exact 64-bit integer arithmetic.
//
// polygon_coverage() applies the same rule to a whole simple polygon. The top-left rule is the same
// as asking whether the point p + (e, e^2) is strictly inside, for an infinitesimal e > 0 (shift right
// by e, and down by the much smaller e^2 so that horizontal edges are decided too). A tiling of a
// polygon by triangles therefore covers exactly the pixels polygon_coverage() reports, each once:
// that is what the watertightness tests compare against.
#pragma once

#include <cstdint>
#include <vector>

#include "facet/math/vec.hpp"
#include "facet/pipeline.hpp"

namespace facet_test::raster {

constexpr std::int64_t k_sub = 256;  // fixed-point units per pixel

// A point in fixed point: 1/256 pixel units, screen space (y down).
struct Fixed {
    std::int64_t x = 0, y = 0;
    friend constexpr bool operator==(Fixed, Fixed) = default;
};

constexpr Fixed pixel_centre(std::int64_t ix, std::int64_t iy) {
    return {ix * k_sub + k_sub / 2, iy * k_sub + k_sub / 2};
}

// Half-open pixel rectangle [x0, x1) x [y0, y1).
struct Box {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Twice the signed area of (a, b, c) in y-down screen space (positive: clockwise to the viewer).
std::int64_t signed_area2(Fixed a, Fixed b, Fixed c);

// True when point p is covered by triangle v under the top-left rule (see above).
bool covers(const Fixed (&v)[3], Fixed p);

// Per-pixel coverage of a width x height target (row-major), only pixels inside `box` considered.
using Mask = std::vector<std::uint8_t>;
Mask rasterize(const Fixed (&v)[3], int width, int height, Box box);
// Adds 1 to counts[y * width + x] for every covered pixel inside `box`.
void rasterize_add(const Fixed (&v)[3], int width, Box box, std::vector<int>& counts);

// Pixels of a width x height target whose centre p has p + (e, e^2) strictly inside the simple
// polygon `poly` (either orientation), by exact even-odd crossing counts per row.
Mask polygon_coverage(const std::vector<Fixed>& poly, int width, int height);

// Clip-space position that the renderer projects and snaps exactly to `p`, for the viewport `vp`
// (vp.width, vp.height powers of two), window depth z and clip w:
//   ndc_x = (p.x / 256 - vp.x) * 2 / vp.width - 1,  ndc_y = 1 - (p.y / 256 - vp.y) * 2 / vp.height,
//   clip = (ndc_x * w, ndc_y * w, z * w, w).
// The result is exact only when w is a power of two and the coordinates are moderate (within the
// guard band); check with snaps_exactly().
facet::Vec4 clip_from_fixed(Fixed p, const facet::Rect& vp, float z = 0.5f, float w = 1.0f);

// True when every float step of the documented projection of clip_from_fixed(p, vp, z, w),
//   sx = vp.x + (x / w + 1) * vp.width / 2,  sy = vp.y + (1 - y / w) * vp.height / 2,
// is exact and sx * 256, sy * 256 are exactly p.x, p.y: then rounding to the 1/256 grid gives p
// whatever the rounding mode, and the renderer sees exactly the triangle the reference sees.
bool snaps_exactly(Fixed p, const facet::Rect& vp, float z = 0.5f, float w = 1.0f);

}  // namespace facet_test::raster
