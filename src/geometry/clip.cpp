// facet geometry: Sutherland-Hodgman clipping in homogeneous clip space.
#include "geometry/clip.hpp"

#include <cmath>

namespace facet::detail {
namespace {

// Signed distance to a plane, in float (classification) or double (intersections).
template <class T = float>
T plane_distance(int plane, Vec4 p, GuardBand g) {
    const T x = p.x, y = p.y, z = p.z, w = p.w, gx = g.gx, gy = g.gy;
    switch (plane) {
        case 0: return w - T{k_min_clip_w};
        case 1: return z;
        case 2: return w - z;
        case 3: return x + gx * w;
        case 4: return gx * w - x;
        case 5: return y + gy * w;
        default: return gy * w - y;
    }
}

// The point where edge (inside -> outside) crosses the plane, with interpolated varyings. Computed in
// double, and the coordinate the plane constrains is then set so that the point lies exactly on it:
// in float, in + (out - in) * t cancels catastrophically when the ends differ greatly in size
// (w = 1e6 far ahead, 0.01 at the near plane) and could return w <= 0, a point behind the eye that
// made the front end drop the whole triangle; and out - in can overflow although both ends are finite.
// The varyings of the new vertex `index` of `extras`, each interpolated from the ends' as lerp does.
template <class Lerp>
void interpolate_varyings(const ClipVertex& in, const ClipVertex& out, std::uint32_t index, const ClipVertices& vertices,
                          ClipVertices& extras, const Lerp& lerp) {
    const int n = extras.stride;
    extras.varyings.resize(extras.varyings.size() + static_cast<std::size_t>(n));
    const float* a = varyings_of(in.ref, vertices, extras);  // fetched after the resize above
    const float* b = varyings_of(out.ref, vertices, extras);
    float* dst = extras.varyings.data() + static_cast<std::size_t>(index) * n;
    for (int k = 0; k < n; ++k) dst[k] = static_cast<float>(lerp(a[k], b[k]));
}

ClipVertex intersect(const ClipVertex& in, const ClipVertex& out, int plane, GuardBand g,
                     const ClipVertices& vertices, ClipVertices& extras, const ClipPassVaryings* passes) {
    const double d_in = plane_distance<double>(plane, in.pos, g), d_out = plane_distance<double>(plane, out.pos, g);
    const double t = d_in / (d_in - d_out);
    const auto lerp = [t](float a, float b) { return a + (static_cast<double>(b) - a) * t; };
    double x = lerp(in.pos.x, out.pos.x), y = lerp(in.pos.y, out.pos.y), z = lerp(in.pos.z, out.pos.z),
           w = lerp(in.pos.w, out.pos.w);
    switch (plane) {
        case 0: w = k_min_clip_w; break;
        case 1: z = 0; break;
        case 2: z = w; break;
        case 3: x = -static_cast<double>(g.gx) * w; break;
        case 4: x = static_cast<double>(g.gx) * w; break;
        case 5: y = -static_cast<double>(g.gy) * w; break;
        default: y = static_cast<double>(g.gy) * w; break;
    }
    const std::uint32_t index = static_cast<std::uint32_t>(extras.pos.size());
    extras.pos.push_back({static_cast<float>(x), static_cast<float>(y), static_cast<float>(z), static_cast<float>(w)});
    interpolate_varyings(in, out, index, vertices, extras, lerp);
    if (passes) interpolate_varyings(in, out, index, passes->vertices, passes->extras, lerp);
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
                  ClipVertices& extras, ClipVertex (&out)[k_max_clip_polygon], const ClipPassVaryings* passes) {
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
            if (a_in && !b_in) dst[n++] = intersect(a, b, plane, g, vertices, extras, passes);
            if (!a_in && b_in) dst[n++] = intersect(b, a, plane, g, vertices, extras, passes);
        }
        count = n;
        std::swap(src, dst);
    }
    for (int i = 0; i < count; ++i) out[i] = src[i];
    return count;
}

bool clip_segment(ClipVertex& a, ClipVertex& b, std::uint32_t planes, GuardBand g, const ClipVertices& vertices,
                  ClipVertices& extras, const ClipPassVaryings* passes) {
    for (int plane = 0; plane < k_clip_plane_count; ++plane) {
        if (!(planes & (1u << plane))) continue;
        const bool a_in = plane_distance(plane, a.pos, g) >= 0, b_in = plane_distance(plane, b.pos, g) >= 0;
        if (!a_in && !b_in) return false;
        if (!a_in) a = intersect(b, a, plane, g, vertices, extras, passes);
        if (!b_in) b = intersect(a, b, plane, g, vertices, extras, passes);
    }
    return true;
}

}  // namespace facet::detail
