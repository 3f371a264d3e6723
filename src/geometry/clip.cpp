// facet geometry: Sutherland-Hodgman clipping in homogeneous clip space.
#include "geometry/clip.hpp"

#include <cmath>

namespace facet::detail {
namespace {

float plane_distance(int plane, Vec4 p, GuardBand g) {
    switch (plane) {
        case 0: return p.w - k_min_clip_w;
        case 1: return p.z;
        case 2: return p.w - p.z;
        case 3: return p.x + g.gx * p.w;
        case 4: return g.gx * p.w - p.x;
        case 5: return p.y + g.gy * p.w;
        default: return g.gy * p.w - p.y;
    }
}

const float* varyings_of(std::uint32_t ref, const ClipVertices& vertices, const ClipVertices& extras) {
    return (ref & k_clipped_bit) ? extras.varyings_of(ref & ~k_clipped_bit) : vertices.varyings_of(ref);
}

// The point where edge (inside -> outside) crosses the plane, with interpolated varyings.
ClipVertex intersect(const ClipVertex& in, float d_in, const ClipVertex& out, float d_out,
                     const ClipVertices& vertices, ClipVertices& extras) {
    const float t = d_in / (d_in - d_out);
    const std::uint32_t index = static_cast<std::uint32_t>(extras.pos.size());
    const int n = extras.stride;
    extras.pos.push_back(in.pos + (out.pos - in.pos) * t);
    extras.varyings.resize(extras.varyings.size() + static_cast<std::size_t>(n));
    const float* a = varyings_of(in.ref, vertices, extras);  // fetched after the resize above
    const float* b = varyings_of(out.ref, vertices, extras);
    float* dst = extras.varyings.data() + static_cast<std::size_t>(index) * n;
    for (int k = 0; k < n; ++k) dst[k] = a[k] + (b[k] - a[k]) * t;
    return {extras.pos.back(), index | k_clipped_bit};
}

}  // namespace

std::uint32_t outcode(Vec4 p, GuardBand g) {
    std::uint32_t code = 0;
    for (int plane = 0; plane < k_clip_plane_count; ++plane)
        if (plane_distance(plane, p, g) < 0) code |= 1u << plane;
    return code;
}

int clip_triangle(const ClipVertex (&tri)[3], std::uint32_t planes, GuardBand g, const ClipVertices& vertices,
                  ClipVertices& extras, ClipVertex (&out)[k_max_clip_polygon]) {
    ClipVertex buffer[2][k_max_clip_polygon];
    ClipVertex* src = buffer[0];
    ClipVertex* dst = buffer[1];
    int count = 3;
    for (int i = 0; i < 3; ++i) src[i] = tri[i];

    for (int plane = 0; plane < k_clip_plane_count && count > 0; ++plane) {
        if (!(planes & (1u << plane))) continue;
        int n = 0;
        for (int i = 0; i < count; ++i) {
            const ClipVertex& a = src[i];
            const ClipVertex& b = src[(i + 1) % count];
            const float da = plane_distance(plane, a.pos, g), db = plane_distance(plane, b.pos, g);
            const bool a_in = da >= 0, b_in = db >= 0;
            if (n + 2 > k_max_clip_polygon) return 0;
            if (a_in) dst[n++] = a;
            if (a_in && !b_in) dst[n++] = intersect(a, da, b, db, vertices, extras);
            if (!a_in && b_in) dst[n++] = intersect(b, db, a, da, vertices, extras);
        }
        count = n;
        std::swap(src, dst);
    }
    for (int i = 0; i < count; ++i) out[i] = src[i];
    return count;
}

}  // namespace facet::detail
