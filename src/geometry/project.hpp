// facet geometry: projection, from clip space to the screen. In: the vertex stage's ClipVertices (or
// a clipped polygon's vertices). Out: each vertex's outcode against the clip planes and, for a vertex
// inside all of them, its ScreenVertex: divided by w keeping q = 1/w, through the viewport, snapped
// to 1/256 pixel. The guard band, which bounds what projection may be handed, is defined here; the
// planes themselves and clipping are clip.hpp's. Does not assemble, cull or set up triangles.
#pragma once

#include <cstddef>

#include "facet/detail/front_end.hpp"

namespace facet::detail {

// Screen-space x and y are clipped to within k_guard_band_pixels of the viewport centre. Triangles
// reaching past the viewport but inside this band are rasterized without clipping (the bounding box
// is clamped instead); only larger ones are cut. 8192 keeps |x| <= 16384 px = 2^22 in fixed point
// (k_subpixel_bits), with viewports inside [0, k_max_target_size].
constexpr float k_guard_band_pixels = 8192.0f;

// The guard band as clip planes: |x| <= gx * w, |y| <= gy * w.
struct GuardBand {
    float gx, gy;
};

// The guard band of the draw's viewport (k_guard_band_pixels around its centre).
GuardBand guard_band(const FrontEndParams& p);

// Divides by w (keeping q = 1/w), applies the viewport and snaps. Precondition: w > 0 and x, y
// inside the guard band, so the division is safe and the result fits the fixed-point range.
ScreenVertex project(Vec4 pos_clip, const FrontEndParams& params);

// The specification of project_vertices for vertex i at clip position pos: outcode[i]
// (k_outcode_invalid for a non-finite position) and, inside every plane, screen[i] = project(pos);
// zeros elsewhere (never read).
void project_vertex(Vec4 pos, ClipVertices& vertices, std::size_t i, GuardBand guard, const FrontEndParams& p);

// The projection pass: project_vertex for vertices [first, end), pos[j] the position of vertex
// first + j, run after the vertex stage on each of its blocks, so that every vertex is projected once
// rather than once per triangle that uses it. A SIMD kernel with the ISA selected in facet/isa.hpp
// (project_simd.cpp), or project_vertex itself when "scalar" is selected; the same bytes either way.
void project_vertices(const Vec4* pos, ClipVertices& vertices, std::size_t first, std::size_t end,
                      const FrontEndParams& params);
// The same with the positions in vertices.pos.
inline void project_vertices(ClipVertices& vertices, std::size_t first, std::size_t end, const FrontEndParams& params) {
    project_vertices(vertices.pos.data() + first, vertices, first, end, params);
}

}  // namespace facet::detail
