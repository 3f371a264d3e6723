// facet setup: from a clipped triangle to a TriangleSetup.
// In: three clip-space vertices inside the guard band with w > 0. Steps: project (divide by w,
// keep q = 1/w), viewport, snap to 1/256 pixel, cull by the winding the viewer sees, orient
// counter-clockwise in screen space, edge functions with the top-left rule, attribute planes.
// Out: TriangleSetup, or nothing when the triangle is culled, has zero area or covers no pixel centre.
#pragma once

#include <optional>

#include "facet/detail/front_end.hpp"
#include "geometry/clip.hpp"

namespace facet::detail {

enum class SetupResult { ok, culled, empty };

// Divides by w (keeping q = 1/w), applies the viewport and snaps. Precondition: w > 0 and x, y
// inside the guard band, so the division is safe and the result fits the fixed-point range.
ScreenVertex project(Vec4 pos_clip, const FrontEndParams& params);

// `ref` names each vertex's varyings (a ClipVertices index, or k_clipped_bit | extras index).
SetupResult setup_triangle(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], const FrontEndParams& params,
                           TriangleSetup& out);

}  // namespace facet::detail
