// facet raster internals: the edges of a triangle that cross a rectangle of pixels, in the 32-bit form
// the SIMD coverage kernel (coverage_simd.cpp) evaluates.
#pragma once

#include <cstdint>

namespace facet::detail {

struct CrossingEdges {
    int count;                      // 0 to 4 edges (a segment's: 4) that are negative somewhere in the rectangle
    std::int32_t e[4], a[4], b[4];  // value at the rectangle's first pixel, step per column, per row
    int width, height;              // rectangle size in pixels (width <= 64)
    int shift;                      // column of the rectangle's first pixel within its tile row
};

// rows[r] = coverage of row r of the rectangle, shifted left by `shift`. Returns true if any bit is set.
bool cover_rows_simd(const CrossingEdges& edges, std::uint64_t* rows);

}  // namespace facet::detail
