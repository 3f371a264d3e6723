// facet geometry: projection of one vertex, the specification of the projection pass
// (project_simd.cpp), and the guard band it is bounded by.
#include "geometry/project.hpp"

#include <algorithm>

#include "geometry/clip.hpp"

namespace facet::detail {

GuardBand guard_band(const FrontEndParams& p) {
    return {k_guard_band_pixels / (p.vp_w * 0.5f), k_guard_band_pixels / (p.vp_h * 0.5f)};
}

ScreenVertex project(Vec4 p, const FrontEndParams& v) {
    const float q = 1.0f / p.w;
    const float sx = v.vp_x + (p.x * q + 1.0f) * (v.vp_w * 0.5f);
    const float sy = v.vp_y + (1.0f - p.y * q) * (v.vp_h * 0.5f);
    const float z = std::clamp(p.z * q, 0.0f, 1.0f);
    return {static_cast<std::int32_t>(std::lrint(sx * k_subpixel_one)),
            static_cast<std::int32_t>(std::lrint(sy * k_subpixel_one)), z, q};
}

void project_vertex(Vec4 pos, ClipVertices& vertices, std::size_t i, GuardBand guard, const FrontEndParams& p) {
    const auto code = is_finite(pos) ? static_cast<std::uint8_t>(outcode(pos, guard)) : k_outcode_invalid;
    vertices.outcode[i] = code;
    // Zeros outside any plane or invalid, as the SIMD path stores: the array is not cleared first.
    vertices.screen[i] = code == 0 ? project(pos, p) : ScreenVertex{0, 0, 0.0f, 0.0f};
}

}  // namespace facet::detail
