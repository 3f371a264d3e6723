// facet geometry: homogeneous clipping of triangles (clip space in, polygon of clip-space vertices out).
// Planes: w >= epsilon (nothing is ever divided by w <= 0), near z >= 0, far z <= w, and the guard
// band |x| <= gx * w, |y| <= gy * w that bounds screen coordinates for the fixed-point rasterizer
// (project.hpp).
#pragma once

#include <cstdint>

#include "facet/detail/front_end.hpp"
#include "geometry/project.hpp"

namespace facet::detail {

constexpr int k_clip_plane_count = 7;
// Smallest w kept; with any real projection the near plane (z >= 0) removes far more than this.
constexpr float k_min_clip_w = 1e-6f;
// A triangle clipped by 7 planes has at most 3 + 7 vertices; rounding can make a nearly degenerate
// polygon cross a plane more than twice, so leave room, and drop a polygon that would overflow.
constexpr int k_max_clip_polygon = 16;

// Bit p set when pos is outside plane p. Non-finite positions must be rejected before this.
std::uint32_t outcode(Vec4 pos, GuardBand g);

struct ClipVertex {
    Vec4 pos;
    std::uint32_t ref;  // vertex index, or k_clipped_bit | index into `extras`
};

// The render passes' own varyings (DrawPasses: the pass vertex stage's output) and where the
// clip-made vertices' go: at the same index as in the shader's extras.
struct ClipPassVaryings {
    const ClipVertices& vertices;
    ClipVertices& extras;
};

// Clips the triangle against the planes in `planes` (an outcode union). New vertices and their
// interpolated varyings are appended to `extras` (and to `passes`' when given, with the same
// weights). Interpolation always runs from the inside vertex to the outside one, so two triangles
// sharing an edge create the very same vertex on it (no cracks). Returns the number of polygon
// vertices written to `out` (0 when nothing is left).
int clip_triangle(const ClipVertex (&tri)[3], std::uint32_t planes, GuardBand g, const ClipVertices& vertices,
                  ClipVertices& extras, ClipVertex (&out)[k_max_clip_polygon], const ClipPassVaryings* passes = nullptr);

// Clips the segment a-b against the planes in `planes` (an outcode union), in place: an end outside
// a plane is replaced by the crossing, made as clip_triangle makes its vertices (appended to `extras`
// and `passes`' extras). False when nothing is left.
bool clip_segment(ClipVertex& a, ClipVertex& b, std::uint32_t planes, GuardBand g, const ClipVertices& vertices,
                  ClipVertices& extras, const ClipPassVaryings* passes = nullptr);

}  // namespace facet::detail
